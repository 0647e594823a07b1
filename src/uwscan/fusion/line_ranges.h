// Range constraints where map points meet the laser line (thesis §5.4,
// scale equalisation): the sparse map is re-projected into a frame with the
// frame's pose, and a map point whose ray passes next to a point of the
// frame's laser profile gets that point's range along the ray, measured in
// this frame alone. Unlike a depth read from the accumulated surface (built
// from profiles placed with earlier poses, so it drifts with them), this
// measurement does not depend on any other pose: on a long transect it is
// what keeps the odometry's scale from drifting.
#pragma once

#include <vector>

#include "uwscan/geometry/rigid3d.h"
#include "uwscan/laser/profile.h"
#include "uwscan/sensor/camera.h"
#include "uwscan/vo/map.h"

namespace uwscan::fusion {

struct LineRangeOptions {
  // A laser point counts for a map point when it lies within this distance
  // of the point's ray; its range then differs from the point's by the
  // scene's slope across the line times this offset. That slope is not
  // measured (one profile), so the constraint's sigma allows for the
  // steepest slope along the line nearby (the same relief, assumed
  // isotropic), at least min_slope:
  //   sigma = base_sigma_m + max(min_slope, slope along the line) * offset.
  double max_offset_m = 0.01;
  double base_sigma_m = 0.001;
  double min_slope = 0.2;
  int slope_neighbours = 8;  // profile points on each side for the slope
  // A laser range this far (relative) from the map point's current range
  // is another surface on the same ray (an edge, an occluder), not kept.
  double max_relative_disagreement = 0.25;
  void Check() const;
};

// `camera` is the one the odometry tracks with (the ray origins must be
// those of the bundle adjustment); `profile` is the frame's, in the camera
// frame (metric, so any resolution's camera will do for it).
std::vector<vo::RangeConstraint> LineRangeConstraints(const Camera& camera,
                                                      const vo::SparseMap& map,
                                                      const Rigid3d& camera_from_world,
                                                      const laser::Profile& profile,
                                                      const LineRangeOptions& options = {});

}  // namespace uwscan::fusion
