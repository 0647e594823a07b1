#include "uwscan/calib/laser_points.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "uwscan/calib/board_render.h"

namespace uwscan {
namespace {

// A rendered board with a green laser line (blurred Gaussian profile): the
// extracted pixels lie on the line, inside the board.
TEST(LaserPoints, ExtractsTheGreenLineOnTheBoard) {
  const BoardSpec board{9, 6, 0.03};
  const Eigen::Quaterniond rotation(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY()));
  const Rigid3d pose(
      rotation, Eigen::Vector3d(0.0, 0.0, 0.45) - rotation * Eigen::Vector3d(0.12, 0.075, 0.0));
  BoardRenderOptions render;
  render.blur_sigma_px = 0.7;
  std::vector<Eigen::Vector2d> corners;
  const cv::Mat gray = RenderBoard(board, pose, render, &corners);
  cv::Mat bgr;
  cv::cvtColor(gray, bgr, cv::COLOR_GRAY2BGR);
  // Near-vertical line x = a + b y in pixels, drawn as a Gaussian profile.
  const double a = 610.3, b = 0.05;
  cv::Mat laser(bgr.size(), CV_32F, cv::Scalar(0));
  for (int y = 0; y < laser.rows; ++y) {
    for (int x = 0; x < laser.cols; ++x) {
      const double d = x - (a + b * y);
      laser.at<float>(y, x) = static_cast<float>(150.0 * std::exp(-0.5 * d * d / 1.5));
    }
  }
  std::vector<cv::Mat> channels;
  cv::split(bgr, channels);
  cv::Mat green;
  channels[1].convertTo(green, CV_32F);
  green += laser;
  green.convertTo(channels[1], CV_8U);
  cv::merge(channels, bgr);

  const auto pixels = ExtractLaserPixels(bgr, board, corners);
  ASSERT_GT(pixels.size(), 100u);
  double max_error = 0.0;
  for (const auto& p : pixels) max_error = std::max(max_error, std::abs(p.x() - (a + b * p.y())));
  // CoG over +-3 px; on white squares the line saturates at 255 (measured
  // worst case 0.27 px), hence not tighter.
  EXPECT_LT(max_error, 0.3);
}

}  // namespace
}  // namespace uwscan
