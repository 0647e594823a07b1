#include "uwscan/pipeline/vo_dataset.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

namespace uwscan {
namespace {

TEST(TrackingImage, TakesTheGreenOfBayerAndColour) {
  // RGGB mosaic of a uniform colour (R 200, G 100, B 50): green is 100.
  cv::Mat mosaic(8, 8, CV_8U);
  for (int v = 0; v < 8; ++v) {
    for (int u = 0; u < 8; ++u) {
      mosaic.at<uint8_t>(v, u) = (v % 2 == 0 && u % 2 == 0)   ? 200
                                 : (v % 2 == 1 && u % 2 == 1) ? 50
                                                              : 100;
    }
  }
  const cv::Mat green = TrackingImage(mosaic, "rggb");
  ASSERT_EQ(green.type(), CV_8UC1);
  EXPECT_EQ(green.at<uint8_t>(4, 4), 100);
  cv::Mat bgr(4, 4, CV_8UC3, cv::Scalar(50, 100, 200));
  EXPECT_EQ(TrackingImage(bgr, "none").at<uint8_t>(1, 1), 100);
  EXPECT_TRUE(TrackingImage(cv::Mat(), "none").empty());
}

}  // namespace
}  // namespace uwscan
