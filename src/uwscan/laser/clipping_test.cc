#include "uwscan/laser/clipping.h"

#include <gtest/gtest.h>

namespace uwscan::laser {
namespace {

// A vertical line at column u on every row, as DetectLaserLine reports it.
std::vector<LaserPoint> VerticalLine(double u, int rows) {
  std::vector<LaserPoint> line;
  for (int v = 0; v < rows; ++v) line.push_back({u, double(v)});
  return line;
}

// A 100x80 grey image with a clipped 20x10 patch (columns 10-29, rows
// 40-49) and a line clipped 3 px wide at column 70 (69-71).
cv::Mat MonoScene() {
  cv::Mat image(80, 100, CV_8U, cv::Scalar(100));
  image(cv::Rect(10, 40, 20, 10)).setTo(255);
  image.colRange(69, 72).setTo(255);
  return image;
}

TEST(MeasureClipping, CountsTheClippedSceneButNotTheLine) {
  const cv::Mat image = MonoScene();
  const ClippedScene scene = MeasureClipping(image, ColourLayout::kMono, kGreen, /*scan_rows=*/true,
                                             VerticalLine(70.0, 80), /*every_rows=*/1, 12.0);
  EXPECT_EQ(scene.clipped, 200);               // the patch
  EXPECT_EQ(scene.examined, 80 * (100 - 25));  // columns 58-82 are the line's
  EXPECT_DOUBLE_EQ(scene.Share(), 200.0 / 6000.0);
  // Without the line's points its own clipped pixels count too.
  const ClippedScene all = MeasureClipping(image, ColourLayout::kMono, kGreen, true, {}, 1, 12.0);
  EXPECT_EQ(all.clipped, 200 + 80 * 3);
  EXPECT_EQ(all.examined, 8000);
  // Every 4th row: rows 0, 4, ..., 76, of which 40, 44 and 48 cross the patch.
  const ClippedScene sparse =
      MeasureClipping(image, ColourLayout::kMono, kGreen, true, VerticalLine(70.0, 80), 4, 12.0);
  EXPECT_EQ(sparse.clipped, 3 * 20);
  EXPECT_EQ(sparse.examined, 20 * 75);
  // Scan lines without a point of the line are looked at whole.
  const ClippedScene half =
      MeasureClipping(image, ColourLayout::kMono, kGreen, true, VerticalLine(70.0, 40), 1, 12.0);
  EXPECT_EQ(half.clipped, 200 + 40 * 3);
  EXPECT_EQ(half.examined, 40 * 75 + 40 * 100);
}

TEST(MeasureClipping, ScanningColumnsLeavesOutTheRowsAroundTheLine) {
  cv::Mat image(80, 100, CV_8U, cv::Scalar(100));
  image.rowRange(29, 32).setTo(255);          // a horizontal line at row 30
  image(cv::Rect(50, 60, 10, 5)).setTo(255);  // a clipped patch below it
  std::vector<LaserPoint> line;
  for (int u = 0; u < 100; ++u) line.push_back({double(u), 30.0});
  const ClippedScene scene =
      MeasureClipping(image, ColourLayout::kMono, kGreen, /*scan_rows=*/false, line, 1, 12.0);
  EXPECT_EQ(scene.clipped, 50);
  EXPECT_EQ(scene.examined, (80 - 25) * 100);  // rows 18-42 are the line's
}

TEST(MeasureClipping, OnlyTheLasersColourCounts) {
  // RGGB: red at (even, even), green at (even, odd) and (odd, even).
  cv::Mat image(8, 8, CV_8U, cv::Scalar(50));
  for (int r = 0; r < 8; r += 2)
    for (int c = 0; c < 8; c += 2) image.at<uint8_t>(r, c) = 255;  // red clipped everywhere
  const ClippedScene green = MeasureClipping(image, ColourLayout::kBayerRggb, kGreen, true, {}, 1);
  EXPECT_EQ(green.clipped, 0);
  EXPECT_EQ(green.examined, 32);  // half the pixels are green
  const ClippedScene red = MeasureClipping(image, ColourLayout::kBayerRggb, kRed, true, {}, 1);
  EXPECT_EQ(red.clipped, 16);
  EXPECT_EQ(red.examined, 16);
  image.at<uint8_t>(1, 0) = 255;  // one green pixel
  EXPECT_EQ(MeasureClipping(image, ColourLayout::kBayerRggb, kGreen, true, {}, 1).clipped, 1);

  cv::Mat bgr(4, 4, CV_8UC3, cv::Scalar(10, 20, 255));  // red clipped
  EXPECT_EQ(MeasureClipping(bgr, ColourLayout::kBgr, kGreen, true, {}, 1).clipped, 0);
  EXPECT_EQ(MeasureClipping(bgr, ColourLayout::kBgr, kRed, true, {}, 1).clipped, 16);
}

TEST(MeasureClipping, SixteenBitFullScaleIsTheTopTenthOfAPercent) {
  cv::Mat image(2, 4, CV_16U, cv::Scalar(65000));
  image.at<uint16_t>(0, 0) = 65535;
  image.at<uint16_t>(0, 1) = 65520;  // 12-bit full scale, shifted up by 4 bits
  image.at<uint16_t>(1, 0) = 65400;
  const ClippedScene scene = MeasureClipping(image, ColourLayout::kMono, kGreen, true, {}, 1);
  EXPECT_EQ(scene.clipped, 2);
  EXPECT_EQ(scene.examined, 8);
}

TEST(MeasureClipping, BadInputIsAnError) {
  EXPECT_THROW(MeasureClipping(cv::Mat(4, 4, CV_32F), ColourLayout::kMono, kGreen, true, {}),
               std::exception);
  EXPECT_THROW(MeasureClipping(cv::Mat(4, 4, CV_8U), ColourLayout::kMono, kGreen, true, {}, 0),
               std::exception);
}

}  // namespace
}  // namespace uwscan::laser
