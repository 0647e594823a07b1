#include "uwscan/calib/board_pose.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "uwscan/calib/camera_bundle.h"
#include "uwscan/util/error.h"

namespace uwscan {

std::optional<BoardPose> EstimateBoardPose(const Camera& camera, const BoardSpec& board,
                                           const std::vector<Eigen::Vector2d>& corners) {
  const std::vector<Eigen::Vector3d> points = board.Corners();
  if (corners.size() != points.size() || points.size() < 4) return std::nullopt;
  const double scale = camera.IsFlatPort() ? camera.port.n_air / camera.port.n_water : 1.0;
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image;
  for (size_t i = 0; i < points.size(); ++i) {
    double x, y;
    if (!PinholeModel::ImageToNormalized(camera.intrinsics.data(), camera.distortion.data(),
                                         corners[i].x(), corners[i].y(), &x, &y)) {
      return std::nullopt;
    }
    object.emplace_back(points[i].x(), points[i].y(), points[i].z());
    image.emplace_back(x * scale, y * scale);
  }
  cv::Mat rvec, tvec;
  const cv::Mat identity = cv::Mat::eye(3, 3, CV_64F);
  if (!cv::solvePnP(object, image, identity, cv::noArray(), rvec, tvec, false, cv::SOLVEPNP_IPPE)) {
    return std::nullopt;
  }
  cv::Mat rotation_cv;
  cv::Rodrigues(rvec, rotation_cv);
  Eigen::Matrix3d rotation;
  cv::cv2eigen(rotation_cv, rotation);
  const Rigid3d initial(
      Eigen::Quaterniond(rotation),
      Eigen::Vector3d(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2)));
  if (!(initial.translation.z() > 0.0)) return std::nullopt;

  // Pose-only refinement with the camera's own model.
  CornerSet set;
  set.board = board;
  set.width = camera.width;
  set.height = camera.height;
  set.views.push_back({"pose", corners});
  CameraBundleOptions options;
  options.free = CameraParameterMask{false, false, false, false, false, false, true};
  options.max_iterations = 50;
  Camera fixed = camera;
  std::vector<Rigid3d> poses = {initial};
  try {
    const CameraBundleResult result = SolveCameraBundle(set, {true}, options, &fixed, &poses);
    if (!std::isfinite(result.view_rms_px[0])) return std::nullopt;
    return BoardPose{poses[0], result.view_rms_px[0]};
  } catch (const Error&) {
    return std::nullopt;
  }
}

}  // namespace uwscan
