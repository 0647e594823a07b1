#include "uwscan/calib/camera_calibration.h"

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <sstream>

#include "uwscan/calib/board_pose.h"
#include "uwscan/util/error.h"
#include "uwscan/util/statistics.h"

namespace uwscan {
namespace {

std::string Format(double value, int precision = 3) {
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(precision);
  out << value;
  return out.str();
}

// Tab. 4.11: under water the port is free, the lens optionally too.
CameraBundleOptions WaterBundleOptions(const WaterRefinementOptions& options,
                                       bool free_intrinsics) {
  CameraBundleOptions bundle;
  bundle.free.intrinsics = free_intrinsics;
  bundle.free.distortion = options.free_distortion;
  bundle.free.fix_k3 = options.common.fix_k3;
  bundle.free.normal = true;
  bundle.free.d_air = true;
  bundle.free.n_water = options.estimate_n_water;
  bundle.residual = options.residual;
  bundle.taylor_iterations = options.taylor_iterations;
  bundle.max_iterations = options.common.max_iterations;
  bundle.compute_covariance = options.common.compute_covariance;
  return bundle;
}

}  // namespace

void OutlierOptions::Check() const {
  UWS_CHECK(max_view_rms_px > 0.0, "outlier threshold must be positive");
  UWS_CHECK(max_view_rms_factor >= 1.0, "outlier factor must be >= 1");
  UWS_CHECK(max_rounds >= 0, "max_rounds must be >= 0");
  UWS_CHECK(min_views >= 1, "min_views must be >= 1");
}

void CameraCalibrationOptions::Check() const {
  outliers.Check();
  UWS_CHECK(max_iterations > 0, "max_iterations must be positive");
}

void FlatPortAirOptions::Check() const {
  common.Check();
  UWS_CHECK(d_glass > 0.0 && d_glass < 0.2, "glass thickness must be in (0, 0.2) m, got ", d_glass);
  UWS_CHECK(n_glass >= 1.0 && n_glass < 3.0, "glass index must be in [1, 3), got ", n_glass);
  UWS_CHECK(n_air >= 1.0 && n_air < 1.1, "air index must be in [1, 1.1), got ", n_air);
  UWS_CHECK(d_air >= 0.0 && d_air < 0.5, "d_air must be in [0, 0.5) m, got ", d_air);
}

void WaterRefinementOptions::Check() const {
  common.Check();
  UWS_CHECK(n_water >= 1.0 && n_water < 2.0, "water index must be in [1, 2), got ", n_water);
  UWS_CHECK(taylor_iterations >= 1 && taylor_iterations <= 10,
            "taylor_iterations must be in [1, 10]");
}

CameraCalibrationResult SolveWithOutlierLoop(const CornerSet& set, Camera camera,
                                             std::vector<Rigid3d> poses, std::vector<bool> use,
                                             std::vector<std::string> reasons,
                                             const CameraBundleOptions& bundle,
                                             const OutlierOptions& outliers,
                                             const std::string& stage) {
  outliers.Check();
  CameraCalibrationResult result;
  result.stage = stage;
  CameraBundleResult solved;
  for (int round = 0;; ++round) {
    const int used = static_cast<int>(std::count(use.begin(), use.end(), true));
    UWS_CHECK(used >= outliers.min_views, stage, " calibration: only ", used,
              " usable view(s), need at least ", outliers.min_views);
    // Covariance only for the final solve (below).
    CameraBundleOptions options = bundle;
    options.compute_covariance = false;
    solved = SolveCameraBundle(set, use, options, &camera, &poses);
    std::vector<double> used_rms;
    for (size_t v = 0; v < use.size(); ++v) {
      if (use[v]) used_rms.push_back(solved.view_rms_px[v]);
    }
    const double threshold =
        std::max(outliers.max_view_rms_px, outliers.max_view_rms_factor * Median(used_rms));
    int worst = -1;
    for (size_t v = 0; v < use.size(); ++v) {
      if (!use[v]) continue;
      const double rms = solved.view_rms_px[v];
      if (!std::isfinite(rms) || rms > threshold) {
        if (worst < 0 || !std::isfinite(rms) || rms > solved.view_rms_px[worst]) worst = v;
      }
    }
    if (worst < 0 || round >= outliers.max_rounds) break;
    use[worst] = false;
    reasons[worst] = std::isfinite(solved.view_rms_px[worst])
                         ? "re-projection RMS " + Format(solved.view_rms_px[worst]) +
                               " px above threshold " + Format(threshold) + " px"
                         : "corners do not project with the solved model";
    result.outlier_rounds = round + 1;
  }
  if (bundle.compute_covariance) {
    CameraBundleOptions options = bundle;
    solved = SolveCameraBundle(set, use, options, &camera, &poses);
  }
  result.camera = camera;
  result.rms_px = solved.rms_px;
  result.iterations = solved.iterations;
  result.converged = solved.converged;
  result.parameters = solved.parameters;
  result.residuals = solved.residuals;
  for (size_t v = 0; v < set.views.size(); ++v) {
    ViewReport view;
    view.name = set.views[v].name;
    view.used = use[v];
    view.dropped_reason = use[v] ? "" : reasons[v];
    view.rms_px = solved.view_rms_px[v];
    view.camera_from_board = poses[v];
    result.views.push_back(view);
    result.used_views += use[v];
  }
  return result;
}

CameraCalibrationResult CalibratePinhole(const CornerSet& set, const Camera& camera_template,
                                         const CameraCalibrationOptions& options) {
  options.Check();
  set.Check("pinhole calibration");
  UWS_CHECK(static_cast<int>(set.views.size()) >= options.outliers.min_views,
            "pinhole calibration: ", set.views.size(), " view(s) with a board, need at least ",
            options.outliers.min_views);
  // Zhang's closed form and OpenCV's LM as the start.
  const std::vector<Eigen::Vector3d> points = set.board.Corners();
  std::vector<std::vector<cv::Point3f>> object(set.views.size());
  std::vector<std::vector<cv::Point2f>> image(set.views.size());
  for (size_t v = 0; v < set.views.size(); ++v) {
    for (size_t i = 0; i < points.size(); ++i) {
      object[v].emplace_back(points[i].x(), points[i].y(), points[i].z());
      image[v].emplace_back(set.views[v].corners[i].x(), set.views[v].corners[i].y());
    }
  }
  cv::Mat camera_matrix, distortion;
  std::vector<cv::Mat> rvecs, tvecs;
  const int flags = options.fix_k3 ? cv::CALIB_FIX_K3 : 0;
  const double opencv_rms = cv::calibrateCamera(object, image, cv::Size(set.width, set.height),
                                                camera_matrix, distortion, rvecs, tvecs, flags);
  Camera camera = camera_template;
  camera.model = CameraModelId::kPinhole;
  camera.width = set.width;
  camera.height = set.height;
  camera.intrinsics = {camera_matrix.at<double>(0, 0), camera_matrix.at<double>(1, 1),
                       camera_matrix.at<double>(0, 2), camera_matrix.at<double>(1, 2)};
  for (int i = 0; i < 5; ++i) camera.distortion[i] = distortion.at<double>(i);
  std::vector<Rigid3d> poses;
  for (size_t v = 0; v < set.views.size(); ++v) {
    cv::Mat rotation_cv;
    cv::Rodrigues(rvecs[v], rotation_cv);
    Eigen::Matrix3d rotation;
    cv::cv2eigen(rotation_cv, rotation);
    poses.emplace_back(
        Eigen::Quaterniond(rotation),
        Eigen::Vector3d(tvecs[v].at<double>(0), tvecs[v].at<double>(1), tvecs[v].at<double>(2)));
  }
  CameraBundleOptions bundle;
  bundle.free.fix_k3 = options.fix_k3;
  bundle.max_iterations = options.max_iterations;
  bundle.compute_covariance = options.compute_covariance;
  CameraCalibrationResult result = SolveWithOutlierLoop(
      set, camera, poses, std::vector<bool>(set.views.size(), true),
      std::vector<std::string>(set.views.size()), bundle, options.outliers, "pinhole");
  result.opencv_rms_px = opencv_rms;
  return result;
}

CameraCalibrationResult CalibrateFlatPortInAir(const CornerSet& set,
                                               const CameraCalibrationResult& pinhole,
                                               const FlatPortAirOptions& options) {
  options.Check();
  set.Check("flat-port calibration in air");
  Camera camera = pinhole.camera;
  camera.model = CameraModelId::kFlatPort;
  camera.port.normal = Eigen::Vector3d::UnitZ();
  camera.port.d_air = options.d_air;
  camera.port.d_glass = options.d_glass;
  camera.port.n_air = options.n_air;
  camera.port.n_glass = options.n_glass;
  camera.port.n_water = options.n_air;  // in air on both sides (Tab. 4.10)
  std::vector<Rigid3d> poses;
  std::vector<bool> use;
  std::vector<std::string> reasons;
  for (const ViewReport& view : pinhole.views) {
    poses.push_back(view.camera_from_board);
    use.push_back(view.used);
    reasons.push_back(view.dropped_reason);
  }
  CameraBundleOptions bundle;
  bundle.free.fix_k3 = options.common.fix_k3;
  bundle.max_iterations = options.common.max_iterations;
  bundle.compute_covariance = options.common.compute_covariance;
  return SolveWithOutlierLoop(set, camera, poses, use, reasons, bundle, options.common.outliers,
                              "flatport-air");
}

CameraCalibrationResult RefineFlatPortInWater(const CornerSet& water, const Camera& in_air,
                                              const WaterRefinementOptions& options) {
  options.Check();
  water.Check("flat-port refinement in water");
  UWS_CHECK(in_air.IsFlatPort(), "flat-port refinement in water: the in-air camera '", in_air.name,
            "' is not a flat-port camera");
  UWS_CHECK(water.width == in_air.width && water.height == in_air.height,
            "flat-port refinement in water: water images are ", water.width, "x", water.height,
            " but the in-air calibration is ", in_air.width, "x", in_air.height);
  Camera camera = in_air;
  camera.port.n_water = options.n_water;
  std::vector<Rigid3d> poses;
  std::vector<bool> use;
  std::vector<std::string> reasons;
  for (const ViewCorners& view : water.views) {
    const auto pose = EstimateBoardPose(camera, water.board, view.corners);
    poses.push_back(pose ? pose->camera_from_board : Rigid3d());
    use.push_back(pose.has_value());
    reasons.push_back(pose ? "" : "no board pose found with the in-air model");
  }
  return SolveWithOutlierLoop(water, camera, poses, use, reasons,
                              WaterBundleOptions(options, options.free_intrinsics),
                              options.common.outliers, "flatport-water");
}

namespace {

// The joint bundle of air and water views; `camera` starts it, the air views
// start from the poses of `air_result` and the water views from poses found
// with `camera`.
CameraCalibrationResult SolveJoint(const CornerSet& air, const CameraCalibrationResult& air_result,
                                   const CornerSet& water, Camera camera, bool air_without_port,
                                   const WaterRefinementOptions& options) {
  options.Check();
  air.Check("joint flat-port calibration (air views)");
  water.Check("joint flat-port calibration (water views)");
  UWS_CHECK(air_result.views.size() == air.views.size(),
            "joint flat-port calibration: needs the in-air result of the same views");
  UWS_CHECK(water.width == air.width && water.height == air.height,
            "joint flat-port calibration: water images are ", water.width, "x", water.height,
            " but air images are ", air.width, "x", air.height);
  UWS_CHECK(water.board.cols == air.board.cols && water.board.rows == air.board.rows &&
                water.board.square_m == air.board.square_m,
            "joint flat-port calibration: air and water views must use the same board");
  camera.port.n_water = options.n_water;
  CornerSet joint = air;
  std::vector<Rigid3d> poses;
  std::vector<bool> use, in_air;
  std::vector<std::string> reasons;
  for (size_t v = 0; v < air.views.size(); ++v) {
    joint.views[v].name = "air/" + air.views[v].name;
    poses.push_back(air_result.views[v].camera_from_board);
    use.push_back(air_result.views[v].used);
    reasons.push_back(air_result.views[v].dropped_reason);
    in_air.push_back(true);
  }
  for (const ViewCorners& view : water.views) {
    const auto pose = EstimateBoardPose(camera, water.board, view.corners);
    joint.views.push_back({"water/" + view.name, view.corners});
    poses.push_back(pose ? pose->camera_from_board : Rigid3d());
    use.push_back(pose.has_value());
    reasons.push_back(pose ? "" : "no board pose found with the starting model");
    in_air.push_back(false);
  }
  CameraBundleOptions bundle = WaterBundleOptions(options, true);
  if (air_without_port) {
    bundle.view_without_port = in_air;
  } else {
    bundle.view_in_air = in_air;
  }
  return SolveWithOutlierLoop(joint, camera, poses, use, reasons, bundle, options.common.outliers,
                              air_without_port ? "flatport-joint-portless-air" : "flatport-joint");
}

}  // namespace

CameraCalibrationResult CalibrateFlatPortJoint(const CornerSet& air,
                                               const CameraCalibrationResult& air_result,
                                               const CornerSet& water,
                                               const WaterRefinementOptions& options) {
  UWS_CHECK(air_result.camera.IsFlatPort(),
            "joint flat-port calibration: needs the flat-port in-air result");
  return SolveJoint(air, air_result, water, air_result.camera, false, options);
}

CameraCalibrationResult CalibrateFlatPortJointPortlessAir(const CornerSet& air,
                                                          const CameraCalibrationResult& pinhole,
                                                          const CornerSet& water,
                                                          const Camera& start,
                                                          const WaterRefinementOptions& options) {
  UWS_CHECK(start.IsFlatPort(), "joint flat-port calibration: the start camera '", start.name,
            "' is not a flat-port camera");
  return SolveJoint(air, pinhole, water, start, true, options);
}

}  // namespace uwscan
