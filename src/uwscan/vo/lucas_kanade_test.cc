#include "uwscan/vo/lucas_kanade.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>
#include <random>

namespace uwscan::vo {
namespace {

// A smooth texture known everywhere (a sum of random sinusoids, periods
// 6-40 px), so that a shifted image is exact, not resampled.
class Texture {
 public:
  explicit Texture(uint32_t seed) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<double> angle(0, 2 * M_PI), period(6, 40), phase(0, 2 * M_PI);
    for (int i = 0; i < 24; ++i) {
      const double a = angle(random), k = 2 * M_PI / period(random);
      waves_.push_back({k * std::cos(a), k * std::sin(a), phase(random)});
    }
  }
  // The image with the texture moved by (dx, dy); `flat` blanks a square
  // (no texture there).
  cv::Mat Image(int width, int height, double dx, double dy, cv::Rect flat = {}) const {
    cv::Mat image(height, width, CV_8UC1);
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) {
        double v = 0;
        for (const auto& w : waves_) v += std::cos(w[0] * (x - dx) + w[1] * (y - dy) + w[2]);
        image.at<uint8_t>(y, x) = cv::saturate_cast<uint8_t>(128 + 18 * v);
      }
    }
    if (flat.area() > 0) image(flat).setTo(128);
    return image;
  }

 private:
  std::vector<std::array<double, 3>> waves_;
};

std::vector<cv::Mat> Pyramid(const cv::Mat& image, int window_px, int levels) {
  std::vector<cv::Mat> pyramid;
  const int border = LucasKanadeBorderPx(window_px);
  cv::buildOpticalFlowPyramid(image, pyramid, cv::Size(border, border), levels, false);
  return pyramid;
}

std::vector<cv::Point2f> Grid(int width, int height, int margin, int step) {
  std::vector<cv::Point2f> points;
  for (int y = margin; y < height - margin; y += step)
    for (int x = margin; x < width - margin; x += step) points.emplace_back(x + 0.3f, y + 0.6f);
  return points;
}

TEST(LucasKanade, FindsAKnownShiftOverThePyramid) {
  const Texture texture(7);
  const double dx = 11.37, dy = -6.81;  // beyond one level's reach
  const std::vector<cv::Mat> from = Pyramid(texture.Image(320, 240, 0, 0), 21, 3);
  const std::vector<cv::Mat> to = Pyramid(texture.Image(320, 240, dx, dy), 21, 3);
  const std::vector<cv::Point2f> points = Grid(320, 240, 40, 20);
  std::vector<cv::Point2f> tracked;
  std::vector<uint8_t> status;
  TrackLucasKanade(from, to, points, &tracked, &status, 3, false, {});
  ASSERT_EQ(tracked.size(), points.size());
  double worst = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    ASSERT_TRUE(status[i]) << i;
    worst = std::max(worst,
                     std::hypot(tracked[i].x - points[i].x - dx, tracked[i].y - points[i].y - dy));
  }
  // 8-bit images: a few hundredths of a pixel.
  EXPECT_LT(worst, 0.05);
}

TEST(LucasKanade, RefinesFromAGuessOnOneLevel) {
  const Texture texture(11);
  const double dx = 0.43, dy = 0.71;
  const std::vector<cv::Mat> from = Pyramid(texture.Image(200, 160, 0, 0), 15, 0);
  const std::vector<cv::Mat> to = Pyramid(texture.Image(200, 160, dx, dy), 15, 0);
  const std::vector<cv::Point2f> points = Grid(200, 160, 30, 15);
  std::vector<cv::Point2f> tracked;
  for (const auto& p : points) tracked.push_back(p + cv::Point2f(1.2f, -0.4f));  // the guess
  std::vector<uint8_t> status;
  LucasKanadeOptions options;
  options.window_px = 15;
  TrackLucasKanade(from, to, points, &tracked, &status, 0, true, options);
  for (size_t i = 0; i < points.size(); ++i) {
    ASSERT_TRUE(status[i]) << i;
    EXPECT_NEAR(tracked[i].x - points[i].x, dx, 0.05) << i;
    EXPECT_NEAR(tracked[i].y - points[i].y, dy, 0.05) << i;
  }
}

TEST(LucasKanade, AgreesWithOpenCv) {
  // An independent implementation of the same method on the same images.
  const Texture texture(3);
  const cv::Mat a = texture.Image(320, 240, 0, 0), b = texture.Image(320, 240, 2.6, 1.9);
  const std::vector<cv::Point2f> points = Grid(320, 240, 30, 12);
  std::vector<cv::Point2f> ours, theirs;
  std::vector<uint8_t> status, their_status;
  TrackLucasKanade(Pyramid(a, 21, 2), Pyramid(b, 21, 2), points, &ours, &status, 2, false, {});
  std::vector<float> error;
  cv::calcOpticalFlowPyrLK(a, b, points, theirs, their_status, error, cv::Size(21, 21), 2);
  double sum = 0;
  int both = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    if (!status[i] || !their_status[i]) continue;
    ++both;
    sum += std::hypot(ours[i].x - theirs[i].x, ours[i].y - theirs[i].y);
  }
  EXPECT_GT(both, 0.95 * points.size());
  EXPECT_LT(sum / both, 0.02);
}

TEST(LucasKanade, LosesWindowsWithoutTextureAndPointsLeavingTheImage) {
  const Texture texture(5);
  const cv::Rect flat(100, 80, 60, 60);
  const std::vector<cv::Mat> from = Pyramid(texture.Image(320, 240, 0, 0, flat), 21, 0);
  const std::vector<cv::Mat> to = Pyramid(texture.Image(320, 240, 0.5, 0.5, flat), 21, 0);
  const std::vector<cv::Point2f> points = {{130, 110}, {60, 60}};
  std::vector<cv::Point2f> tracked = {{130, 110}, {-80, 60}};  // the second starts far off
  std::vector<uint8_t> status;
  TrackLucasKanade(from, to, points, &tracked, &status, 0, true, {});
  EXPECT_EQ(status[0], 0);  // flat: no gradient
  EXPECT_EQ(status[1], 0);  // its window cannot be read there
  // Not finite: lost, not thrown.
  tracked = {{NAN, 1}};
  TrackLucasKanade(from, to, {{60, 60}}, &tracked, &status, 0, true, {});
  EXPECT_EQ(status[0], 0);
}

TEST(LucasKanade, PortableKernelsGiveTheSameBits) {
  const Texture texture(9);
  // Borders for the widest window.
  const std::vector<cv::Mat> from = Pyramid(texture.Image(240, 200, 0, 0), 31, 2);
  const std::vector<cv::Mat> to = Pyramid(texture.Image(240, 200, 3.3, -1.7), 31, 2);
  const std::vector<cv::Point2f> points = Grid(240, 200, 25, 9);
  for (int window : {9, 21, 31}) {
    LucasKanadeOptions options;
    options.window_px = window;
    std::vector<cv::Point2f> vector, portable;
    std::vector<uint8_t> vector_status, portable_status;
    TrackLucasKanade(from, to, points, &vector, &vector_status, 2, false, options);
    options.allow_avx2 = false;
    TrackLucasKanade(from, to, points, &portable, &portable_status, 2, false, options);
    EXPECT_EQ(vector_status, portable_status) << window;
    for (size_t i = 0; i < points.size(); ++i) {
      EXPECT_EQ(vector[i].x, portable[i].x) << window << " " << i;
      EXPECT_EQ(vector[i].y, portable[i].y) << window << " " << i;
    }
  }
}

TEST(LucasKanade, RefusesBadOptionsAndNarrowBorders) {
  const Texture texture(1);
  const cv::Mat image = texture.Image(100, 80, 0, 0);
  std::vector<cv::Point2f> tracked;
  std::vector<uint8_t> status;
  LucasKanadeOptions options;
  options.window_px = 20;  // even
  EXPECT_THROW(TrackLucasKanade(Pyramid(image, 21, 0), Pyramid(image, 21, 0), {{50, 40}}, &tracked,
                                &status, 0, false, options),
               std::exception);
  // A plain image has no border to read windows at its edges from.
  EXPECT_THROW(TrackLucasKanade({image}, {image}, {{50, 40}}, &tracked, &status, 0, false, {}),
               std::exception);
}

}  // namespace
}  // namespace uwscan::vo
