// One Ceres bundle adjustment over checkerboard views: camera parameter
// groups and board poses, any group held constant (thesis §4.4, Tab. 4.10
// and 4.11). The calibration procedures in camera_calibration.h call this
// with different free groups.
#pragma once

#include <string>
#include <vector>

#include "uwscan/calib/board.h"
#include "uwscan/calib/reprojection_costs.h"
#include "uwscan/geometry/rigid3d.h"
#include "uwscan/sensor/camera.h"

namespace uwscan {

// Which parameter groups are free. Port groups only apply to flat ports.
struct CameraParameterMask {
  bool intrinsics = true;
  bool distortion = true;
  bool fix_k3 = false;  // hold k3 even when the distortion is free
  bool normal = false;
  bool d_air = false;
  bool n_water = false;
  bool poses = true;
};

struct CameraBundleOptions {
  CameraParameterMask free;
  FlatPortResidualType residual = FlatPortResidualType::kExact;
  int taylor_iterations = 2;
  int max_iterations = 200;
  bool compute_covariance = false;
  // Flat port only: views with view_in_air[v] see air behind the glass
  // (n_water = n_air, held constant), the others the camera's water. Empty:
  // all views under the camera's water. Lets air and water views share one
  // bundle (joint refinement).
  std::vector<bool> view_in_air;
  // Flat port only: views with view_without_port[v] were taken without the
  // port (camera calibrated in air before it goes behind the window, thesis
  // §6.1): straight rays, only intrinsics and distortion act on them. Empty:
  // every view through the port.
  std::vector<bool> view_without_port;
  void Check() const;
};

// A value with its standard deviation from the covariance (NaN if held
// constant or the covariance is unavailable).
struct ParameterEstimate {
  std::string name;
  double value = 0.0;
  double std_dev = 0.0;
};

struct CornerResidual {
  int view = 0;
  double u = 0.0, v = 0.0;    // measured corner (px)
  double du = 0.0, dv = 0.0;  // projected - measured (px)
};

struct CameraBundleResult {
  bool converged = false;
  int iterations = 0;
  double rms_px = 0.0;                        // sqrt(mean |r|^2) over corners of the used views
  std::vector<double> view_rms_px;            // every view (NaN where a corner does not project)
  std::vector<CornerResidual> residuals;      // used views
  std::vector<ParameterEstimate> parameters;  // free camera parameters
  bool covariance_ok = false;
};

// Refines `camera` and `camera_from_board` (one pose per view of `set`) over
// the views with use_view[i]. Throws uwscan::Error if fewer than one view is
// used or a pose cannot be evaluated at the start.
CameraBundleResult SolveCameraBundle(const CornerSet& set, const std::vector<bool>& use_view,
                                     const CameraBundleOptions& options, Camera* camera,
                                     std::vector<Rigid3d>* camera_from_board);

// Re-projection errors of one view with fixed parameters: per-corner
// residual vectors (projected - measured); false entries where a corner does
// not project.
std::vector<Eigen::Vector2d> ViewResiduals(const Camera& camera, const BoardSpec& board,
                                           const ViewCorners& view,
                                           const Rigid3d& camera_from_board,
                                           std::vector<bool>* valid);

}  // namespace uwscan
