// Per-frame fusion of both modalities in the pose (thesis §5.4): the
// odometry's pose is refined jointly on the passive features (re-projection
// of their map points) and on the frame's laser profile, whose points must
// lie on the surface the laser measured before (point-to-plane distances
// with a Cauchy loss, eq. 5.3). The features fix the motion along the
// surface, the profile the distance and tilt to it, which the features of a
// nearly planar scene determine poorly.
#pragma once

#include <optional>
#include <vector>

#include "uwscan/fusion/surface_model.h"
#include "uwscan/laser/profile.h"
#include "uwscan/vo/odometry.h"

namespace uwscan::fusion {

struct PoseRefinementOptions {
  double feature_sigma_px = 0.5;
  double laser_sigma_m = 0.0005;
  double cauchy_scale = 3.0;  // in sigmas
  int max_profile_points = 80;
  int min_profile_points = 10;
  int max_iterations = 10;
};

struct PoseRefinementResult {
  Rigid3d world_from_camera;
  int feature_residuals = 0;
  int laser_residuals = 0;
  bool refined = false;
};

PoseRefinementResult RefinePoseWithProfile(const Camera& camera, const vo::Odometry& odometry,
                                           const Rigid3d& world_from_camera,
                                           const laser::Profile& profile,
                                           const SurfaceModel& surface,
                                           const PoseRefinementOptions& options = {});

}  // namespace uwscan::fusion
