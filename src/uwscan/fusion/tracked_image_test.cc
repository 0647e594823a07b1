// The tracked image's pieces (tracked_image.cc): the LED colour's samples
// of a raw mosaic and their mean over frames, the passive colour of other
// frames, and the illumination normalisation.
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <vector>

#include "uwscan/fusion/self_referenced.h"
#include "uwscan/util/error.h"

namespace uwscan::fusion {
namespace {

TEST(SelfReferenced, BayerSamplesOfTheLedColour) {
  using P = SelfReferencedPoseProvider;
  EXPECT_EQ(P::BayerSampleOffset("rggb", laser::kRed), cv::Point(0, 0));
  EXPECT_EQ(P::BayerSampleOffset("bggr", laser::kRed), cv::Point(1, 1));
  EXPECT_EQ(P::BayerSampleOffset("grbg", laser::kRed), cv::Point(1, 0));
  EXPECT_EQ(P::BayerSampleOffset("gbrg", laser::kRed), cv::Point(0, 1));
  EXPECT_EQ(P::BayerSampleOffset("rggb", laser::kBlue), cv::Point(1, 1));
  EXPECT_FALSE(P::BayerSampleOffset("rggb", laser::kGreen).has_value());
  EXPECT_FALSE(P::BayerSampleOffset("none", laser::kRed).has_value());
  cv::Mat mosaic(4, 6, CV_16U);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 6; ++c) mosaic.at<uint16_t>(r, c) = static_cast<uint16_t>(100 * r + c);
  const cv::Mat red = P::BayerChannel(mosaic, cv::Point(1, 0));  // grbg
  ASSERT_EQ(red.size(), cv::Size(3, 2));
  EXPECT_EQ(red.at<uint16_t>(1, 2), 100 * 2 + 5);
  // The mean of two mosaics' samples, unrounded, in 8-bit grey levels.
  const cv::Mat brighter = mosaic + cv::Scalar(7);
  const cv::Mat mean = P::BayerChannelMean({mosaic, brighter}, cv::Point(1, 0));
  ASSERT_EQ(mean.size(), cv::Size(3, 2));
  ASSERT_EQ(mean.type(), CV_32F);
  EXPECT_FLOAT_EQ(mean.at<float>(1, 2), (100 * 2 + 5 + 3.5f) / 256.0f);
  EXPECT_FLOAT_EQ(mean.at<float>(0, 0), (1 + 3.5f) / 256.0f);
  // Colour frames: the passive colour's mean.
  cv::Mat a(2, 2, CV_8UC3, cv::Scalar(0, 50, 100)), b(2, 2, CV_8UC3, cv::Scalar(0, 90, 103));
  const cv::Mat colour_mean = P::TrackedPassiveImage(std::vector<cv::Mat>{a, b}, "none",
                                                     laser::kGreen, std::nullopt, cv::Size(2, 2));
  ASSERT_EQ(colour_mean.type(), CV_32F);
  EXPECT_FLOAT_EQ(colour_mean.at<float>(1, 1), 101.5f);  // red, not the laser's green
  EXPECT_THROW(P::BayerChannelMean({mosaic, cv::Mat(4, 6, CV_8U, cv::Scalar(0))}, cv::Point(0, 0)),
               Error);
}

TEST(SelfReferenced, PassiveImageAvoidsTheLaserColour) {
  // A raw RGGB mosaic: red pixels 200, the rest 10.
  cv::Mat mosaic(8, 8, CV_8U, cv::Scalar(10));
  for (int r = 0; r < 8; r += 2) {
    for (int c = 0; c < 8; c += 2) mosaic.at<uint8_t>(r, c) = 200;
  }
  const cv::Mat red = SelfReferencedPoseProvider::PassiveImage(mosaic, "rggb", laser::kGreen);
  ASSERT_EQ(red.channels(), 1);
  EXPECT_GT(cv::mean(red)[0], 150.0);
  const cv::Mat mono(8, 8, CV_8U, cv::Scalar(5));
  EXPECT_EQ(SelfReferencedPoseProvider::PassiveImage(mono, "none", laser::kGreen).data, mono.data);
  // A smooth shading ramp vanishes under the illumination normalisation.
  cv::Mat ramp(64, 64, CV_8U);
  for (int r = 0; r < 64; ++r) ramp.row(r).setTo(cv::Scalar(50 + 2 * r));
  const cv::Mat flat = SelfReferencedPoseProvider::NormalizeIllumination(ramp, 6.0);
  cv::Scalar mean, stddev;
  cv::meanStdDev(flat(cv::Rect(16, 16, 32, 32)), mean, stddev);
  EXPECT_NEAR(mean[0], 128.0, 2.0);
  EXPECT_LT(stddev[0], 2.0);
}

// The fast high pass (blur of a 4x smaller image) matches the full-size
// Gaussian one away from the border on texture with strong shading.
TEST(SelfReferencedPoseProvider, FastIlluminationNormalisationMatchesFullGaussian) {
  cv::Mat texture(240, 320, CV_32F);
  cv::randu(texture, 0.0, 60.0);
  cv::GaussianBlur(texture, texture, cv::Size(), 1.2);
  cv::Mat image(texture.size(), CV_8U);
  for (int r = 0; r < image.rows; ++r) {
    for (int c = 0; c < image.cols; ++c) {
      const double d2 = (c - 160.0) * (c - 160.0) + (r - 100.0) * (r - 100.0);
      const double shading = 60.0 + 80.0 * std::exp(-d2 / 9000.0);
      image.at<uint8_t>(r, c) = cv::saturate_cast<uint8_t>(shading + texture.at<float>(r, c));
    }
  }
  const double sigma = 6.4;
  const cv::Mat fast = SelfReferencedPoseProvider::NormalizeIllumination(image, sigma);
  cv::Mat value, background, exact;
  image.convertTo(value, CV_32F);
  cv::GaussianBlur(value, background, cv::Size(), sigma);
  cv::Mat((value - background) * 4.0 + 128.0).convertTo(exact, CV_8U);
  const cv::Rect inner(24, 24, image.cols - 48, image.rows - 48);
  cv::Mat difference;
  cv::absdiff(fast(inner), exact(inner), difference);
  cv::Scalar mean, stddev;
  cv::meanStdDev(exact(inner), mean, stddev);
  double max_difference = 0.0;
  cv::minMaxLoc(difference, nullptr, &max_difference);
  EXPECT_GT(stddev[0], 10.0);      // real texture after the high pass
  EXPECT_LE(max_difference, 2.0);  // grey levels, after the x4 gain
  EXPECT_LT(cv::mean(difference)[0], 0.3);
}

// The LED's fall-off scales the texture's contrast across the image (4x
// here); equalising it over a wide Gaussian makes the local contrast even,
// and a frame with no texture (noise only) gains none.
TEST(SelfReferencedPoseProvider, ContrastEqualisationEvensOutTheLightsFallOff) {
  cv::Mat texture(240, 320, CV_32F);
  cv::RNG rng(3);
  rng.fill(texture, cv::RNG::NORMAL, 0.0, 1.0);
  cv::GaussianBlur(texture, texture, cv::Size(), 1.5);
  texture *= 1.0 / std::sqrt(cv::mean(texture.mul(texture))[0]);
  cv::Mat image(texture.size(), CV_8U);
  for (int r = 0; r < image.rows; ++r) {
    for (int c = 0; c < image.cols; ++c) {
      const double light = 40.0 + 120.0 * c / (image.cols - 1.0);  // 40 .. 160
      image.at<uint8_t>(r, c) =
          cv::saturate_cast<uint8_t>(light * (1.0 + 0.08 * texture.at<float>(r, c)));
    }
  }
  const double width = image.cols;
  auto local_rms = [](const cv::Mat& out, int x0) {
    cv::Scalar mean, stddev;
    cv::meanStdDev(out(cv::Rect(x0, 40, 60, 160)), mean, stddev);
    return stddev[0];
  };
  const cv::Mat plain = SelfReferencedPoseProvider::NormalizeIllumination(image, 0.01 * width);
  const cv::Mat even =
      SelfReferencedPoseProvider::NormalizeIllumination(image, 0.01 * width, 0.05 * width);
  EXPECT_GT(local_rms(plain, 250) / local_rms(plain, 10), 2.4);  // the fall-off is there
  EXPECT_NEAR(local_rms(even, 250) / local_rms(even, 10), 1.0, 0.15);
  // Across the middle the equalised contrast is the image's own, not a new scale.
  EXPECT_NEAR(local_rms(even, 130) / local_rms(plain, 130), 1.0, 0.3);

  cv::Mat flat(240, 320, CV_8U);
  rng.fill(flat, cv::RNG::NORMAL, 100.0, 1.0);
  cv::Scalar mean, plain_sd, even_sd;
  cv::meanStdDev(SelfReferencedPoseProvider::NormalizeIllumination(flat, 3.2), mean, plain_sd);
  cv::meanStdDev(SelfReferencedPoseProvider::NormalizeIllumination(flat, 3.2, 16.0), mean, even_sd);
  EXPECT_LT(even_sd[0], 1.2 * plain_sd[0]);
  // A black frame stays black.
  const cv::Mat black(240, 320, CV_8U, cv::Scalar(0));
  cv::meanStdDev(SelfReferencedPoseProvider::NormalizeIllumination(black, 3.2, 16.0), mean,
                 even_sd);
  EXPECT_EQ(even_sd[0], 0.0);
}

}  // namespace
}  // namespace uwscan::fusion
