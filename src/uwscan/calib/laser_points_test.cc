#include "uwscan/calib/laser_points.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "uwscan/calib/board_render.h"

namespace uwscan {
namespace {

// A rendered board with a green laser line (Gaussian profile) that runs on
// beyond the board: the points found lie on the line, and only inside the
// target outline (the board's outer squares plus the margin).
TEST(LaserPoints, FindsTheGreenLineOnTheTargetOnly) {
  const BoardSpec board{9, 6, 0.03};
  const Eigen::Quaterniond rotation(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY()));
  const Rigid3d pose(
      rotation, Eigen::Vector3d(0.0, 0.0, 0.45) - rotation * Eigen::Vector3d(0.12, 0.075, 0.0));
  BoardRenderOptions render;
  render.blur_sigma_px = 0.7;
  render.white = 180.0;  // + the line's 60: no saturation
  std::vector<Eigen::Vector2d> corners;
  const cv::Mat gray = RenderBoard(board, pose, render, &corners);
  const Camera camera = RenderCamera(render);
  // The camera reproduces the renderer's corners.
  const auto first = camera.Project(pose * board.Corners()[0]);
  ASSERT_TRUE(first.has_value());
  ASSERT_LT((*first - corners[0]).norm(), 1e-6);
  cv::Mat bgr;
  cv::cvtColor(gray, bgr, cv::COLOR_GRAY2BGR);
  // Near-vertical line x = a + b y in pixels, over the whole image height.
  const double a = 610.3, b = 0.05;
  for (int y = 0; y < bgr.rows; ++y) {
    for (int x = 0; x < bgr.cols; ++x) {
      const double d = x - (a + b * y);
      cv::Vec3b& px = bgr.at<cv::Vec3b>(y, x);
      px[1] = cv::saturate_cast<uchar>(px[1] + 60.0 * std::exp(-0.5 * d * d / 1.5));
    }
  }
  for (const double margin : {0.0, 0.02}) {
    const std::vector<cv::Point2f> outline = TargetOutline(camera, board, pose, margin);
    const auto pixels = DetectLaserOnTarget(bgr, outline);
    ASSERT_GT(pixels.size(), 100u);
    double max_error = 0.0;
    for (const auto& p : pixels) max_error = std::max(max_error, std::abs(p.x() - (a + b * p.y())));
    EXPECT_LT(max_error, 0.1) << margin;
    // Found on (nearly) every row where the line is on the target, none off it.
    int rows_on_target = 0;
    for (int y = 0; y < bgr.rows; ++y) {
      rows_on_target += cv::pointPolygonTest(outline, cv::Point2f(a + b * y, y), false) > 0;
    }
    std::printf("margin %.2f m: %zu points, line on the target over %d rows\n", margin,
                pixels.size(), rows_on_target);
    EXPECT_GE(pixels.size(), 0.95 * rows_on_target) << margin;
    EXPECT_LE(pixels.size(), rows_on_target + 2) << margin;
  }
}

}  // namespace
}  // namespace uwscan
