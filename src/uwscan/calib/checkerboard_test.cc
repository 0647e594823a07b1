#include "uwscan/calib/checkerboard.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "uwscan/calib/board_render.h"
#include "uwscan/calib/camera_calibration.h"
#include "uwscan/calib/detection_benchmark.h"
#include "uwscan/util/error.h"

namespace uwscan {
namespace {

const BoardSpec kBoard{9, 6, 0.03};

Rigid3d FrontalPose(double range) {
  const Eigen::Quaterniond rotation(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()) *
                                    Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitZ()));
  const Eigen::Vector3d centre(4 * 0.03, 2.5 * 0.03, 0);
  return Rigid3d(rotation, Eigen::Vector3d(0.01, -0.02, range) - rotation * centre);
}

double MatchedRms(const std::vector<Eigen::Vector2d>& found,
                  const std::vector<Eigen::Vector2d>& truth) {
  double forward = 0, backward = 0;
  const size_t n = truth.size();
  for (size_t i = 0; i < n; ++i) {
    forward += (found[i] - truth[i]).squaredNorm();
    backward += (found[i] - truth[n - 1 - i]).squaredNorm();
  }
  return std::sqrt(std::min(forward, backward) / n);
}

TEST(Checkerboard, BothDetectorsFindARenderedBoardSubPixel) {
  BoardRenderOptions render;
  render.blur_sigma_px = 0.7;
  render.noise_sigma = 2.0;
  std::vector<Eigen::Vector2d> truth;
  const cv::Mat image = RenderBoard(kBoard, FrontalPose(0.45), render, &truth);
  for (CornerDetector detector : {CornerDetector::kSectorBased, CornerDetector::kClassic}) {
    DetectionOptions options;
    options.detector = detector;
    const BoardDetection detection = DetectBoard(image, kBoard, options);
    ASSERT_TRUE(detection.found) << CornerDetectorName(detector) << ": " << detection.reason;
    EXPECT_EQ(detection.corners, 54);
    EXPECT_LT(MatchedRms(detection.points, truth), 0.1) << CornerDetectorName(detector);
    EXPECT_GT(detection.edge_width_px, 0.5);
    EXPECT_LT(detection.edge_width_px, 4.0);
  }
}

// A 12-bit camera's frames saved as 16-bit images hold their samples in
// the low bits (up to 4095 of 65535): the board must be found as exactly
// as in the 8-bit image, not after a cut to the top 8 bits (of a dim
// frame's 20 grey levels in 8 bits, 2 are left there).
TEST(Checkerboard, TwelveBitSamplesInSixteenBitImagesKeepTheirPrecision) {
  BoardRenderOptions render;
  render.blur_sigma_px = 0.7;
  render.noise_sigma = 0.5;
  render.black = 2.0;  // a dim frame, as the simulated aquarium's (at most 22)
  render.white = 20.0;
  std::vector<Eigen::Vector2d> truth;
  const cv::Mat image = RenderBoard(kBoard, FrontalPose(0.45), render, &truth);
  cv::Mat twelve_bit;
  image.convertTo(twelve_bit, CV_16U, 16.0);
  const BoardDetection eight = DetectBoard(image, kBoard, DetectionOptions());
  const BoardDetection sixteen = DetectBoard(twelve_bit, kBoard, DetectionOptions());
  ASSERT_TRUE(eight.found) << eight.reason;
  ASSERT_TRUE(sixteen.found) << sixteen.reason;
  const double rms8 = MatchedRms(eight.points, truth);
  const double rms16 = MatchedRms(sixteen.points, truth);
  EXPECT_LT(rms16, 0.1);
  EXPECT_NEAR(rms16, rms8, 0.01);
}

TEST(Checkerboard, RejectsBlurredPartialAndWrongSizeWithReasons) {
  std::vector<Eigen::Vector2d> truth;
  BoardRenderOptions blurred;
  blurred.width = 640;  // VGA: SB's exhaustive search on a failing image is slow
  blurred.height = 480;
  blurred.focal_px = 500.0;
  blurred.blur_sigma_px = 5.0;
  const cv::Mat blurry = RenderBoard(kBoard, FrontalPose(0.45), blurred, &truth);
  DetectionOptions options;
  options.max_edge_width_px = 5.0;
  const BoardDetection blur = DetectBoard(blurry, kBoard, options);
  EXPECT_FALSE(blur.found);
  EXPECT_FALSE(blur.reason.empty());

  // Board shifted half out of the image.
  Rigid3d shifted = FrontalPose(0.45);
  shifted.translation.x() += 0.25;
  BoardRenderOptions vga = blurred;
  vga.blur_sigma_px = 0.5;
  const cv::Mat partial = RenderBoard(kBoard, shifted, vga, &truth);
  const BoardDetection cut = DetectBoard(partial, kBoard, DetectionOptions());
  EXPECT_FALSE(cut.found);
  EXPECT_NE(cut.reason.find("not found"), std::string::npos) << cut.reason;

  const cv::Mat good = RenderBoard(kBoard, FrontalPose(0.45), vga, &truth);
  const BoardDetection wrong = DetectBoard(good, BoardSpec{8, 6, 0.03}, DetectionOptions());
  EXPECT_FALSE(wrong.found);
}

TEST(Checkerboard, DetectionBenchmarkRunsAndSbIsAccurate) {
  const auto conditions = StandardDetectionConditions();
  const auto rows = RunDetectionBenchmark(kBoard, {conditions[0]}, 2, 5);
  ASSERT_EQ(rows.size(), 3u);      // sb, sb-subpix, classic
  EXPECT_EQ(rows[0].detected, 2);  // SB, clear
  EXPECT_LT(rows[0].rms_error_px, 0.2);
}

// OpenCV's real images (Debian opencv-doc): our pinhole calibration agrees
// with cv::calibrateCamera on the same corners.
TEST(Checkerboard, OpenCvSampleImagesPinholeMatchesOpenCv) {
  const std::filesystem::path data = "/usr/share/doc/opencv-doc/examples/data";
  if (!std::filesystem::exists(data / "left01.jpg")) GTEST_SKIP() << "opencv-doc not installed";
  const std::filesystem::path folder =
      std::filesystem::temp_directory_path() / ("uwscan_left_" + std::to_string(getpid()));
  std::filesystem::create_directories(folder);
  for (const auto& entry : std::filesystem::directory_iterator(data)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("left", 0) == 0 && name.size() == 10) {
      std::filesystem::copy_file(entry.path(), folder / name,
                                 std::filesystem::copy_options::overwrite_existing);
    }
  }
  const FolderDetection detection =
      DetectBoardsInFolder(folder, BoardSpec{9, 6, 0.025}, DetectionOptions());
  std::filesystem::remove_all(folder);
  ASSERT_GE(detection.set.views.size(), 10u);
  Camera camera;
  CameraCalibrationOptions options;
  const CameraCalibrationResult result = CalibratePinhole(detection.set, camera, options);
  std::printf("views %zu used %d rms %.4f opencv rms %.4f fx %.3f fy %.3f cx %.3f cy %.3f\n",
              detection.set.views.size(), result.used_views, result.rms_px, result.opencv_rms_px,
              result.camera.intrinsics[0], result.camera.intrinsics[1], result.camera.intrinsics[2],
              result.camera.intrinsics[3]);
  for (const auto& view : result.views) {
    if (!view.used) std::printf("dropped %s: %s\n", view.name.c_str(), view.dropped_reason.c_str());
  }
  // Reference: cv::calibrateCamera on the same corners of the used views.
  std::vector<std::vector<cv::Point3f>> object;
  std::vector<std::vector<cv::Point2f>> image;
  for (size_t v = 0; v < detection.set.views.size(); ++v) {
    if (!result.views[v].used) continue;
    object.emplace_back();
    image.emplace_back();
    for (const auto& p : detection.set.board.Corners()) object.back().emplace_back(p.x(), p.y(), 0);
    for (const auto& c : detection.set.views[v].corners) image.back().emplace_back(c.x(), c.y());
  }
  cv::Mat k, d;
  std::vector<cv::Mat> rvecs, tvecs;
  const double cv_rms = cv::calibrateCamera(object, image, cv::Size(640, 480), k, d, rvecs, tvecs);
  std::printf("cv::calibrateCamera: fx %.3f fy %.3f rms %.4f\n", k.at<double>(0, 0),
              k.at<double>(1, 1), cv_rms);
  EXPECT_NEAR(result.camera.intrinsics[0], k.at<double>(0, 0), 0.5);
  EXPECT_NEAR(result.camera.intrinsics[1], k.at<double>(1, 1), 0.5);
  EXPECT_NEAR(result.rms_px, cv_rms, 0.02);
  EXPECT_GT(result.rms_px, 0.0);
}

TEST(Checkerboard, FolderErrors) {
  const std::filesystem::path folder =
      std::filesystem::temp_directory_path() / ("uwscan_det_" + std::to_string(getpid()));
  std::filesystem::create_directories(folder);
  EXPECT_THROW(DetectBoardsInFolder(folder, kBoard, DetectionOptions()), Error);  // empty
  cv::imwrite((folder / "a.png").string(), cv::Mat(480, 640, CV_8U, cv::Scalar(128)));
  EXPECT_THROW(DetectBoardsInFolder(folder, kBoard, DetectionOptions()), Error);  // no board
  cv::imwrite((folder / "b.png").string(), cv::Mat(400, 640, CV_8U, cv::Scalar(128)));
  try {
    DetectBoardsInFolder(folder, kBoard, DetectionOptions());
    ADD_FAILURE() << "different sizes accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("same size"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(folder);
}

// Board images exported as RGBA PNGs (an alpha channel) are found as the
// colour images they are; OpenCV's detector refuses four channels.
TEST(Checkerboard, RgbaImagesInAFolder) {
  const std::filesystem::path folder =
      std::filesystem::temp_directory_path() / ("uwscan_rgba_" + std::to_string(getpid()));
  std::filesystem::create_directories(folder);
  std::vector<Eigen::Vector2d> truth;
  const cv::Mat image = RenderBoard(kBoard, FrontalPose(0.45), BoardRenderOptions(), &truth);
  cv::Mat rgba;
  cv::cvtColor(image, rgba, image.channels() == 1 ? cv::COLOR_GRAY2BGRA : cv::COLOR_BGR2BGRA);
  ASSERT_TRUE(cv::imwrite((folder / "a.png").string(), rgba));
  const FolderDetection detected = DetectBoardsInFolder(folder, kBoard, DetectionOptions());
  ASSERT_EQ(detected.set.views.size(), 1u);
  EXPECT_LT(MatchedRms(detected.set.views.front().corners, truth), 0.1);
  std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace uwscan
