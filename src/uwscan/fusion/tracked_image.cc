// What the self-referenced odometry (and `uwscan vo`) tracks: the passive
// colour of a raw or colour frame, halved to the tracking width, its line
// mask at that size, and the illumination normalisation. Static members of
// SelfReferencedPoseProvider (self_referenced.h).
#include <cmath>
#include <cstdint>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "uwscan/fusion/self_referenced.h"
#include "uwscan/io/image.h"
#include "uwscan/util/error.h"

namespace uwscan::fusion {

std::optional<cv::Point> SelfReferencedPoseProvider::BayerSampleOffset(const std::string& bayer,
                                                                       int rgb_channel) {
  // Column, row of the channel's sample in each 2x2 cell (green: none, two).
  const char wanted = rgb_channel == laser::kRed ? 'r' : rgb_channel == laser::kBlue ? 'b' : 'g';
  if (bayer.size() != 4 || wanted == 'g') return std::nullopt;
  const size_t at = bayer.find(wanted);
  if (at == std::string::npos || bayer.find(wanted, at + 1) != std::string::npos)
    return std::nullopt;
  return cv::Point(static_cast<int>(at % 2), static_cast<int>(at / 2));
}

Camera SelfReferencedPoseProvider::BayerChannelCamera(const Camera& camera,
                                                      const cv::Point& offset) {
  Camera half = camera;
  half.width /= 2;
  half.height /= 2;
  half.intrinsics = {camera.intrinsics[0] / 2, camera.intrinsics[1] / 2,
                     (camera.intrinsics[2] - offset.x) / 2, (camera.intrinsics[3] - offset.y) / 2};
  return half;
}

int SelfReferencedPoseProvider::TrackingHalvings(int width, int max_width) {
  int halvings = 0;
  while (max_width > 0 && (width >> halvings) > max_width && (width >> halvings) >= 320) {
    ++halvings;
  }
  return halvings;
}

Camera SelfReferencedPoseProvider::TrackingCamera(const Camera& camera, int halvings,
                                                  const std::optional<cv::Point>& bayer_offset) {
  // Further halving averages 2x2 blocks (pixel centres scale about -0.5).
  if (bayer_offset && halvings > 0) {
    return ScaledCamera(BayerChannelCamera(camera, *bayer_offset), 1.0 / (1 << (halvings - 1)));
  }
  return ScaledCamera(camera, 1.0 / (1 << halvings));
}

cv::Mat SelfReferencedPoseProvider::TrackedPassiveImage(
    const cv::Mat& raw, const std::string& bayer, int laser_channel,
    const std::optional<cv::Point>& bayer_offset, const cv::Size& tracked) {
  // The passive colour's own samples of the raw mosaic: half resolution
  // without demosaicking (the tracking camera accounts for their offset).
  cv::Mat passive =
      bayer_offset ? BayerChannel(raw, *bayer_offset) : PassiveImage(raw, bayer, laser_channel);
  if (passive.size() != tracked) cv::resize(passive, passive, tracked, 0, 0, cv::INTER_AREA);
  return passive;
}

namespace {

// 8-bit grey levels per sample value: the unit the tracked image's high
// pass works in (16-bit samples / 256).
double GreyLevelScale(int depth) { return depth == CV_16U ? 1.0 / 256.0 : 1.0; }

}  // namespace

cv::Mat SelfReferencedPoseProvider::TrackedPassiveImage(
    const std::vector<cv::Mat>& raws, const std::string& bayer, int laser_channel,
    const std::optional<cv::Point>& bayer_offset, const cv::Size& tracked) {
  UWS_CHECK(!raws.empty(), "self-referenced odometry: no frame to track");
  if (raws.size() == 1)
    return TrackedPassiveImage(raws.front(), bayer, laser_channel, bayer_offset, tracked);
  cv::Mat passive;
  if (bayer_offset) {
    passive = BayerChannelMean(raws, *bayer_offset);
  } else {
    const cv::Mat first = PassiveImage(raws.front(), bayer, laser_channel);
    cv::Mat sum(first.size(), CV_MAKETYPE(CV_32F, first.channels()), cv::Scalar::all(0));
    for (const cv::Mat& raw : raws) {
      const cv::Mat channel =
          &raw == &raws.front() ? first : PassiveImage(raw, bayer, laser_channel);
      UWS_CHECK(channel.size() == first.size() && channel.type() == first.type(),
                "self-referenced odometry: frames of different sizes or types averaged");
      cv::accumulate(channel, sum);
    }
    sum.convertTo(passive, sum.type(),
                  GreyLevelScale(first.depth()) / static_cast<double>(raws.size()));
  }
  if (passive.size() != tracked) cv::resize(passive, passive, tracked, 0, 0, cv::INTER_AREA);
  return passive;
}

cv::Mat SelfReferencedPoseProvider::TrackedMask(const cv::Mat& mask, const cv::Size& tracked) {
  if (mask.empty() || mask.size() == tracked) return mask;
  cv::Mat small;
  cv::resize(mask, small, tracked, 0, 0, cv::INTER_AREA);
  cv::threshold(small, small, 0, 255, cv::THRESH_BINARY);
  return small;
}

cv::Mat SelfReferencedPoseProvider::BayerChannel(const cv::Mat& raw, const cv::Point& offset) {
  UWS_CHECK(raw.channels() == 1, "self-referenced odometry: expected a raw Bayer frame, got ",
            raw.channels(), " channels");
  cv::Mat channel(raw.rows / 2, raw.cols / 2, raw.type());
  for (int y = 0; y < channel.rows; ++y) {
    if (raw.depth() == CV_16U) {
      const uint16_t* in = raw.ptr<uint16_t>(2 * y + offset.y) + offset.x;
      uint16_t* out = channel.ptr<uint16_t>(y);
      for (int x = 0; x < channel.cols; ++x) out[x] = in[2 * x];
    } else {
      const uint8_t* in = raw.ptr<uint8_t>(2 * y + offset.y) + offset.x;
      uint8_t* out = channel.ptr<uint8_t>(y);
      for (int x = 0; x < channel.cols; ++x) out[x] = in[2 * x];
    }
  }
  return channel;
}

cv::Mat SelfReferencedPoseProvider::BayerChannelMean(const std::vector<cv::Mat>& raws,
                                                     const cv::Point& offset) {
  UWS_CHECK(!raws.empty(), "self-referenced odometry: no frame to track");
  const cv::Mat& first = raws.front();
  for (const cv::Mat& raw : raws) {
    UWS_CHECK(raw.channels() == 1 && raw.size() == first.size() && raw.type() == first.type(),
              "self-referenced odometry: raw frames of different sizes or types averaged");
  }
  cv::Mat channel(first.rows / 2, first.cols / 2, CV_32F, cv::Scalar(0));
  const float scale = static_cast<float>(GreyLevelScale(first.depth()) / raws.size());
  for (int y = 0; y < channel.rows; ++y) {
    float* out = channel.ptr<float>(y);
    for (const cv::Mat& raw : raws) {
      if (raw.depth() == CV_16U) {
        const uint16_t* in = raw.ptr<uint16_t>(2 * y + offset.y) + offset.x;
        for (int x = 0; x < channel.cols; ++x) out[x] += in[2 * x];
      } else {
        const uint8_t* in = raw.ptr<uint8_t>(2 * y + offset.y) + offset.x;
        for (int x = 0; x < channel.cols; ++x) out[x] += in[2 * x];
      }
    }
    for (int x = 0; x < channel.cols; ++x) out[x] *= scale;
  }
  return channel;
}

cv::Mat SelfReferencedPoseProvider::PassiveImage(const cv::Mat& image, const std::string& bayer,
                                                 int laser_channel) {
  // Features in a colour the laser does not light.
  const int passive_rgb = PassiveColour(laser_channel);
  cv::Mat channel;
  if (image.channels() == 3) {
    cv::extractChannel(image, channel, 2 - passive_rgb);
  } else if (bayer != "none") {
    cv::extractChannel(DemosaicToBgr(image, bayer), channel, 2 - passive_rgb);
  } else {
    channel = image;
  }
  return channel;
}

namespace {

// Gaussian blur for a smooth result, on a `factor` times smaller image
// (block averages, whose own blur is taken off the Gaussian's): a fraction
// of the work of the full-size blur. Returns the small image.
cv::Mat BlurredSmall(const cv::Mat& value, double sigma_px, int factor) {
  cv::Mat blurred;
  if (factor == 1) {
    cv::GaussianBlur(value, blurred, cv::Size(), sigma_px);
    return blurred;
  }
  cv::Mat small;
  cv::resize(value, small, cv::Size(), 1.0 / factor, 1.0 / factor, cv::INTER_AREA);
  const double block_variance = (factor * factor - 1) / 12.0;
  const double sigma_small = std::sqrt(sigma_px * sigma_px - block_variance) / factor;
  cv::GaussianBlur(small, blurred, cv::Size(), sigma_small, 0.0, cv::BORDER_REFLECT);
  return blurred;
}

// A small smooth image interpolated back to `size`.
cv::Mat Upsampled(const cv::Mat& small, const cv::Size& size) {
  if (small.size() == size) return small;
  cv::Mat result;
  cv::resize(small, result, size, 0, 0, cv::INTER_LINEAR);
  return result;
}

}  // namespace

cv::Mat SelfReferencedPoseProvider::NormalizeIllumination(const cv::Mat& image, double sigma_px,
                                                          double contrast_sigma_px,
                                                          double log_offset) {
  // The lights travel with the camera, so the scene's shading moves across
  // the image from frame to frame and pulls Lucas-Kanade off the texture.
  // Subtracting the local mean (a high pass) keeps the texture only.
  cv::Mat value, result;
  image.convertTo(value, CV_32F, GreyLevelScale(image.depth()));
  const bool big = image.cols >= 64 && image.rows >= 64;
  // The light also multiplies the texture, and across a patch its gain
  // changes as the patch moves through the fall-off: Lucas-Kanade then
  // reads part of the change as motion. In logarithm the gain is an
  // offset, which the high pass removes. The offset added first (a
  // fraction of the image's mean) keeps the dark parts' noise from being
  // raised as much as their texture; the result is in grey levels of the
  // image's mean (a change of 1 % reads as 1 % of the mean).
  double log_unit = 0.0;
  if (log_offset > 0.0) {
    const double mean = cv::mean(value)[0];
    if (mean > 0.0) {
      value += log_offset * mean;
      cv::log(value, value);
      log_unit = mean;
    }
  }
  cv::Mat texture = value - Upsampled(BlurredSmall(value, sigma_px, sigma_px >= 4.0 && big ? 4 : 1),
                                      value.size());
  if (contrast_sigma_px > 0) {
    // The light also scales the texture's contrast, and that scale moves
    // across the image with the camera too. On the simulator's transects
    // the tracks then lagged the true motion (0.08 px after 8 frames, 0.03
    // px equalised) and the odometry pitched steadily. Equalise the
    // contrast to the image's own (local RMS over contrast_sigma_px),
    // within 1/4..4x, so that a textureless frame gains no texture.
    // The gain is smooth: computed on the small image the local RMS is
    // blurred on, then interpolated back (a fifth of the work).
    const cv::Mat energy = BlurredSmall(texture.mul(texture), contrast_sigma_px,
                                        contrast_sigma_px >= 16.0 && big ? 8 : 1);
    const double global = std::sqrt(cv::mean(energy)[0]);
    if (global > 0) {
      cv::Mat gain;
      cv::sqrt(cv::max(energy, global * global / 16.0), gain);
      cv::divide(global, gain, gain);
      gain = cv::max(cv::min(gain, 4.0), 0.25);
      texture = texture.mul(Upsampled(gain, texture.size()));
    }
  }
  if (log_unit > 0.0) texture *= log_unit;
  cv::Mat high_pass = texture * 4.0 + 128.0;
  high_pass.convertTo(result, CV_8U);
  return result;
}

}  // namespace uwscan::fusion
