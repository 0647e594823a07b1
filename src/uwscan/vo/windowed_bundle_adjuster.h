// Windowed bundle adjustment (thesis §5.2): the last n keyframes and the
// points they see, re-projection residuals through the flat-port model
// (exact or Taylor) or a pinhole, a robust loss, poses on Ceres manifolds.
// The oldest keyframes of the window are held fixed (gauge and, for a
// monocular camera, scale). Work per call is bounded by the window size and
// an iteration/time budget.
#pragma once

#include <ceres/ceres.h>

#include <functional>
#include <unordered_map>
#include <vector>

#include "uwscan/sensor/camera.h"
#include "uwscan/vo/map.h"

namespace uwscan::vo {

// Parameter blocks of a window, for extra residuals (fusion issue).
struct WindowParameters {
  struct Pose {
    double* rotation;     // camera_from_world, Eigen quaternion x y z w
    double* translation;  // camera_from_world
  };
  std::unordered_map<uint64_t, Pose> keyframes;  // by keyframe id
  std::unordered_map<uint64_t, double*> points;  // by point id, world xyz
};
using ExtraResidualCallback = std::function<void(ceres::Problem&, const WindowParameters&)>;

struct BundleAdjustmentOptions {
  int window_size = 7;
  int num_fixed_keyframes = 2;              // oldest keyframes of the window held fixed
  int num_fixed_keyframes_with_ranges = 1;  // when range constraints fix the scale
  // Keyframes just before the window whose observations of the window's
  // points enter the solve with their poses held (as the covisible keyframes
  // outside ORB-SLAM's local BA): a point keeps the rays that placed it
  // after the keyframes that saw it first have left the window.
  int history_keyframes = 7;
  // Keyframes a solve reads: the window and the held ones before it.
  int KeyframesRead() const { return window_size + history_keyframes; }
  ProjectionMethod method = ProjectionMethod::kExact;
  int taylor_iterations = 2;
  double sigma_px = 1.0;
  double huber_px = 1.5;    // robust loss scale (pixels)
  double outlier_px = 3.0;  // observations above are removed after the solve
  // Range constraints (thesis §5.4, eq. 5.3): Cauchy loss of this scale (in
  // sigmas), and after each solve those still this many sigmas off are
  // removed (a feature in front of the surface the laser measured, e.g. a
  // shaft before a hull, or a wrongly extrapolated plane).
  double range_cauchy_sigmas = 2.0;
  double range_outlier_sigmas = 4.0;
  int max_iterations = 10;
  double max_solver_time_s = 0.2;
  ExtraResidualCallback extra_residuals;
  void Check() const;
};

struct BundleAdjustmentSummary {
  int keyframes = 0;
  int points = 0;
  int residuals = 0;
  int range_residuals = 0;
  int removed_range_constraints = 0;
  int iterations = 0;
  double initial_rms_px = 0.0;
  double final_rms_px = 0.0;
  double time_s = 0.0;
  bool converged = false;
  bool time_limited = false;                   // stopped by max_solver_time_s, not converged
  std::vector<uint64_t> removed_observations;  // point ids dropped from the newest keyframe
};

// Adjusts the last `window_size` keyframes of `map` and their points in
// place. With `two_view_init`, the window must hold exactly two keyframes:
// the first is fixed and the second's translation is kept on the unit sphere
// (ceres::SphereManifold), the classic monocular gauge.
BundleAdjustmentSummary AdjustWindow(const Camera& camera, const BundleAdjustmentOptions& options,
                                     SparseMap* map, bool two_view_init = false);

}  // namespace uwscan::vo
