#include "uwscan/pipeline/vo_dataset.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "uwscan/util/error.h"

namespace uwscan {
namespace {

TEST(FramesCsv, ParsesWithAndWithoutLaserAngles) {
  const auto frames = ParseFramesCsv(
      "index,timestamp_s,file\n0,0.0,frames/000000.png\n1,0.5,frames/000001.png\n", "f.csv");
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[1].file, "frames/000001.png");
  EXPECT_DOUBLE_EQ(frames[1].timestamp_s, 0.5);
  EXPECT_FALSE(frames[0].laser_angle_rad.has_value());
  const auto angles =
      ParseFramesCsv("index,timestamp_s,file,laser_angle_rad\n0,1.0,a.png,0.25\n", "f.csv");
  ASSERT_EQ(angles.size(), 1u);
  EXPECT_DOUBLE_EQ(*angles[0].laser_angle_rad, 0.25);
}

TEST(FramesCsv, ErrorsNameFileAndLine) {
  auto message = [](const std::string& text) {
    try {
      ParseFramesCsv(text, "f.csv");
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("idx,t,file\n").find("f.csv:1"), std::string::npos);
  EXPECT_NE(message("index,timestamp_s,file\n0,0,a.png\n1,x,b.png\n").find("f.csv:3"),
            std::string::npos);
  EXPECT_NE(message("index,timestamp_s,file\n0,1,a.png\n1,0.5,b.png\n").find("increase"),
            std::string::npos);
  EXPECT_NE(message("index,timestamp_s,file\n0,1\n").find("expected 3 fields"), std::string::npos);
}

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
