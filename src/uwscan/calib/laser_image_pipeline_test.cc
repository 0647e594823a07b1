// Laser calibration from rendered images, the path `uwscan calibrate laser`
// takes: board detection, board pose, laser pixels on the board, sheet fit.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <opencv2/imgproc.hpp>

#include "uwscan/calib/board_pose.h"
#include "uwscan/calib/board_render.h"
#include "uwscan/calib/calibration_pipeline.h"
#include "uwscan/calib/checkerboard.h"
#include "uwscan/calib/laser_calibration.h"
#include "uwscan/calib/laser_points.h"
#include "uwscan/util/error.h"

namespace uwscan {
namespace {

TEST(LaserImagePipeline, RenderedBoardsWithLaserLineGiveTheSheet) {
  const BoardSpec board{9, 6, 0.03};
  BoardRenderOptions render;
  render.blur_sigma_px = 0.7;
  render.noise_sigma = 2.0;
  const Camera camera = RenderCamera(render);
  // Sheet: laser 0.15 m to the right, toed in by 15 deg, line vertical.
  const double toe = 15.0 * M_PI / 180.0;
  const Eigen::Vector3d laser_centre(0.15, 0.0, 0.0);
  const Eigen::Vector3d sheet_normal(std::cos(toe), 0.0, std::sin(toe));  // x-z plane turned

  std::vector<LaserView> views;
  int k = 0;
  for (double range : {0.40, 0.55, 0.70}) {
    const Eigen::Quaterniond rotation(
        Eigen::AngleAxisd(0.3 * (k++ % 2 ? 1 : -1), Eigen::Vector3d::UnitY()));
    const Rigid3d pose(
        rotation, Eigen::Vector3d(0.0, 0.0, range) - rotation * Eigen::Vector3d(0.12, 0.075, 0.0));
    render.seed = 10 + k;
    std::vector<Eigen::Vector2d> truth;
    const cv::Mat gray = RenderBoard(board, pose, render, &truth);
    // Sheet ∩ board plane: a 3D line; its image is a line for a pinhole.
    const Eigen::Vector3d board_normal = pose.rotation * Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d direction = sheet_normal.cross(board_normal).normalized();
    // A point on both planes: solve the 2x2 system in the span of the normals.
    Eigen::Matrix<double, 2, 3> a;
    a << sheet_normal.transpose(), board_normal.transpose();
    const Eigen::Vector2d b(sheet_normal.dot(laser_centre), board_normal.dot(pose.translation));
    const Eigen::Vector3d point = a.transpose() * (a * a.transpose()).inverse() * b;
    const auto p0 = camera.Project(point - 0.5 * direction);
    const auto p1 = camera.Project(point + 0.5 * direction);
    ASSERT_TRUE(p0 && p1);
    const Eigen::Vector2d line_dir = (*p1 - *p0).normalized();
    cv::Mat bgr;
    cv::cvtColor(gray, bgr, cv::COLOR_GRAY2BGR);
    for (int y = 0; y < bgr.rows; ++y) {
      for (int x = 0; x < bgr.cols; ++x) {
        const Eigen::Vector2d d = Eigen::Vector2d(x, y) - *p0;
        const double distance = d.x() * line_dir.y() - d.y() * line_dir.x();
        const double add = 60.0 * std::exp(-0.5 * distance * distance / 1.5);
        cv::Vec3b& px = bgr.at<cv::Vec3b>(y, x);
        px[1] = cv::saturate_cast<uchar>(px[1] + add);
      }
    }
    const BoardDetection detection = DetectBoard(bgr, board, DetectionOptions());
    ASSERT_TRUE(detection.found) << detection.reason;
    const auto board_pose = EstimateBoardPose(camera, board, detection.points);
    ASSERT_TRUE(board_pose.has_value());
    LaserPointOptions laser_options;
    laser_options.min_peak = 25.0;
    std::string name = "range_";
    name += std::to_string(range);
    views.push_back(
        {name, board_pose->camera_from_board,
         DetectLaserOnTarget(bgr, TargetOutline(camera, board, board_pose->camera_from_board, 0.0),
                             1, laser_options)});
  }
  LaserCalibrationOptions options;
  options.refine_bend = false;
  const LaserCalibrationResult result = CalibrateLaser(camera, views, options);
  const Eigen::Vector3d normal = result.laser.camera_from_laser.RotationMatrix().col(1);
  const double angle_deg =
      std::acos(std::min(1.0, std::abs(normal.dot(sheet_normal)))) * 180.0 / M_PI;
  const double true_baseline = std::abs(sheet_normal.dot(laser_centre));
  std::printf(
      "rendered: normal error %.4f deg, baseline %.3f mm (truth %.3f), plane rms %.3f mm, "
      "%d/%d inliers\n",
      angle_deg, result.baseline_m * 1e3, true_baseline * 1e3, result.plane_rms_m * 1e3,
      result.inliers, result.points);
  EXPECT_LT(angle_deg, 0.1);
  EXPECT_NEAR(result.baseline_m, true_baseline, 5e-4);
  EXPECT_LT(result.plane_rms_m, 2e-4);
}

}  // namespace
}  // namespace uwscan

namespace uwscan {
namespace {

TEST(LaserImagePipeline, ReadsServoAngles) {
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("uwscan_angles_" + std::to_string(getpid()));
  std::ofstream(path) << "file,angle_deg\n000.png,-6\n001.png,3.5\r\n";
  const auto angles = ReadServoAngles(path);
  std::filesystem::remove(path);
  ASSERT_EQ(angles.size(), 2u);
  EXPECT_DOUBLE_EQ(angles.at("000.png"), -6.0 * M_PI / 180.0);
  EXPECT_DOUBLE_EQ(angles.at("001.png"), 3.5 * M_PI / 180.0);
  // Saved by a Windows editor, without a header: the byte order mark is not
  // part of the first image's name.
  std::ofstream(path) << "\xEF\xBB\xBF"
                         "000.png,-6\n";
  const auto marked = ReadServoAngles(path);
  std::filesystem::remove(path);
  EXPECT_EQ(marked.count("000.png"), 1u);
}

// An angle that is no number of degrees, or a second one for an image: the
// error names the file, the line and what is wrong.
TEST(LaserImagePipeline, ServoAngleErrorsNameTheLine) {
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("uwscan_bad_angles_" + std::to_string(getpid()));
  const auto error_of = [&](const std::string& text) {
    std::ofstream(path) << text;
    try {
      ReadServoAngles(path);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string source = path.string();
  EXPECT_EQ(error_of("file,angle_deg\n000.png,nan\n"),
            source + ":2: the angle must be a number of degrees in [-360, 360], got 'nan'");
  EXPECT_EQ(error_of("file,angle_deg\n000.png,1e9\n"),
            source + ":2: the angle must be a number of degrees in [-360, 360], got '1e9'");
  EXPECT_EQ(error_of("file,angle_deg\n000.png,1\n001.png,2\n000.png,3\n"),
            source + ":4: '000.png' is given an angle twice");
  // Radians given as degrees: the views within half a degree.
  EXPECT_EQ(error_of("file,angle_deg\n000.png,-0.2\n001.png,0.1\n002.png,0.3\n"),
            source +
                ": the servo angles span 0.5 degrees (000.png to 002.png): the servo must "
                "turn between the views; in radians? this file takes degrees");
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace uwscan
