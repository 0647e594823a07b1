// Camera calibration from checkerboard corners (thesis §4.4):
//   1. pinhole + Brown in air (Zhang, cv::calibrateCamera start, Ceres refine),
//   2. flat port in air with known glass (Tab. 4.10: normal, d_air and the
//      media held constant),
//   3. refinement under water (Tab. 4.11: normal, d_air and distortion free,
//      intrinsics kept, water index given or estimated),
// each with the outlier loop of §4.4: drop the worst view above the
// threshold, re-solve, until no view is above it.
// The input is corner observations (CornerSet), so images, the simulator and
// synthetic tests all feed the same code.
#pragma once

#include <string>
#include <vector>

#include "uwscan/calib/camera_bundle.h"

namespace uwscan {

struct OutlierOptions {
  double max_view_rms_px = 1.0;      // absolute threshold for a view's RMS
  double max_view_rms_factor = 3.0;  // ... or this times the median view RMS, whichever is larger
  int max_rounds = 20;
  int min_views = 3;  // fewer used views is an error
  void Check() const;
};

struct CameraCalibrationOptions {
  OutlierOptions outliers;
  bool fix_k3 = false;
  bool compute_covariance = true;
  int max_iterations = 200;
  void Check() const;
};

struct FlatPortAirOptions {
  CameraCalibrationOptions common;
  // Tab. 4.10: glass known from the mechanical design; d_air only needs to be
  // smaller than the distance to the target.
  double d_glass = 0.010;
  double n_glass = 1.77;
  double n_air = 1.0;
  double d_air = 0.01;
  void Check() const;
};

struct WaterRefinementOptions {
  CameraCalibrationOptions common;
  double n_water = 1.337;  // fresh ~1.333, sea ~1.34
  bool estimate_n_water = false;
  bool free_distortion = true;  // Tab. 4.11
  bool free_intrinsics = false;
  FlatPortResidualType residual = FlatPortResidualType::kExact;
  int taylor_iterations = 2;
  void Check() const;
};

struct ViewReport {
  std::string name;
  bool used = true;
  std::string dropped_reason;  // empty when used
  double rms_px = 0.0;         // with the final parameters (NaN if it does not project)
  Rigid3d camera_from_board;
};

struct CameraCalibrationResult {
  std::string stage;  // "pinhole", "flatport-air", "flatport-water"
  Camera camera;
  std::vector<ViewReport> views;
  double rms_px = 0.0;  // sqrt(mean |r|^2) over the corners of the used views
  int used_views = 0;
  int iterations = 0;  // of the final solve
  int outlier_rounds = 0;
  bool converged = false;
  std::vector<ParameterEstimate> parameters;
  std::vector<CornerResidual> residuals;
  double opencv_rms_px = -1.0;  // cv::calibrateCamera's RMS on the same corners (pinhole stage)
};

// Stage 1. `camera_template` gives name, image size and bayer; the model of
// the result is pinhole.
CameraCalibrationResult CalibratePinhole(const CornerSet& set, const Camera& camera_template,
                                         const CameraCalibrationOptions& options);

// Stage 2, started from a pinhole result on the same corners.
CameraCalibrationResult CalibrateFlatPortInAir(const CornerSet& set,
                                               const CameraCalibrationResult& pinhole,
                                               const FlatPortAirOptions& options);

// Stage 3: under-water views, started from the in-air flat-port camera.
CameraCalibrationResult RefineFlatPortInWater(const CornerSet& water, const Camera& in_air,
                                              const WaterRefinementOptions& options);

// Stage 2+3 in one bundle: the air views (with the poses of `air_result`)
// and the water views share intrinsics, distortion, normal and d_air; air
// views see air behind the glass. Removes the bias of holding the normal at
// [0, 0, 1] in air and lets the water views sharpen the focal length that
// d_air is correlated with. Views are named "air/<name>" and "water/<name>".
CameraCalibrationResult CalibrateFlatPortJoint(const CornerSet& air,
                                               const CameraCalibrationResult& air_result,
                                               const CornerSet& water,
                                               const WaterRefinementOptions& options);

// The same for air views taken without the port (thesis §6.1: the camera
// calibrated in air, then placed behind the window): the air views, with the
// poses of the pinhole result `pinhole`, are straight-ray views sharing
// intrinsics and distortion with the water views, so the focal length that
// d_air trades against under water is held by the air views. `start` gives
// the port to start from (e.g. RefineFlatPortInWater's result).
CameraCalibrationResult CalibrateFlatPortJointPortlessAir(const CornerSet& air,
                                                          const CameraCalibrationResult& pinhole,
                                                          const CornerSet& water,
                                                          const Camera& start,
                                                          const WaterRefinementOptions& options);

// The outlier loop around a bundle: solves over the views in `use`, drops
// the worst view above the threshold, repeats. Exposed for tests.
CameraCalibrationResult SolveWithOutlierLoop(const CornerSet& set, Camera camera,
                                             std::vector<Rigid3d> poses, std::vector<bool> use,
                                             std::vector<std::string> reasons,
                                             const CameraBundleOptions& bundle,
                                             const OutlierOptions& outliers,
                                             const std::string& stage);

}  // namespace uwscan
