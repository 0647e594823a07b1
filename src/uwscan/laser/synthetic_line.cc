#include "uwscan/laser/synthetic_line.h"

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <random>

namespace uwscan::laser {
namespace {

// Mean of a unit-peak Gaussian profile over the pixel [x - 0.5, x + 0.5].
double PixelIntegratedGaussian(double x, double centre, double sigma) {
  const double scale = 1.0 / (std::sqrt(2.0) * sigma);
  return 0.5 * std::sqrt(2.0 * M_PI) * sigma *
         (std::erf((x + 0.5 - centre) * scale) - std::erf((x - 0.5 - centre) * scale));
}

int ColourAt(ColourLayout layout, int row, int col) {
  const int r = row % 2, c = col % 2;
  switch (layout) {
    case ColourLayout::kBayerRggb:
      return r == 0 ? (c == 0 ? kRed : kGreen) : (c == 0 ? kGreen : kBlue);
    case ColourLayout::kBayerBggr:
      return r == 0 ? (c == 0 ? kBlue : kGreen) : (c == 0 ? kGreen : kRed);
    case ColourLayout::kBayerGrbg:
      return r == 0 ? (c == 0 ? kGreen : kRed) : (c == 0 ? kBlue : kGreen);
    case ColourLayout::kBayerGbrg:
      return r == 0 ? (c == 0 ? kGreen : kBlue) : (c == 0 ? kRed : kGreen);
    default:
      return kMono;
  }
}

}  // namespace

SyntheticLine RenderSyntheticLine(const SyntheticLineOptions& o) {
  std::mt19937 rng(o.seed);
  std::normal_distribution<double> gaussian(0.0, 1.0);
  // Smooth texture: low-resolution noise upsampled.
  cv::Mat coarse(o.height / 8 + 2, o.width / 8 + 2, CV_64F);
  for (int r = 0; r < coarse.rows; ++r) {
    for (int c = 0; c < coarse.cols; ++c) coarse.at<double>(r, c) = gaussian(rng);
  }
  cv::Mat texture;
  cv::resize(coarse, texture, cv::Size(o.width, o.height), 0, 0, cv::INTER_CUBIC);

  SyntheticLine result;
  const int channels = o.layout == ColourLayout::kBgr ? 3 : 1;
  const int type = (o.sixteen_bit ? CV_16U : CV_8U) + ((channels - 1) << CV_CN_SHIFT);
  result.image.create(o.height, o.width, type);
  const double full = o.sixteen_bit ? 65535.0 : 255.0;
  for (int v = 0; v < o.height; ++v) {
    const double dv = v - o.height / 2.0;
    const bool lit = v >= o.first_row && v <= o.last_row;
    const double centre = o.u0 + o.slope * dv + o.curvature * dv * dv;
    if (lit && centre >= 0 && centre <= o.width - 1) result.truth.emplace_back(centre, v);
    const double stripe_centre = o.stripe_u0 + o.stripe_slope * dv;
    for (int u = 0; u < o.width; ++u) {
      // Albedo over the pixel: the share of it before the edge reflects fully.
      const double edge = centre + o.albedo_edge_offset_px;
      const double bright_share = o.albedo_edge ? std::clamp(edge - (u - 0.5), 0.0, 1.0) : 1.0;
      const double albedo = bright_share + (1.0 - bright_share) * o.albedo_dark;
      const double laser =
          lit ? albedo * o.amplitude * PixelIntegratedGaussian(u, centre, o.sigma_px) : 0.0;
      double scene = albedo * (o.background + o.texture * texture.at<double>(v, u));
      if (o.stripe)
        scene += o.stripe_amplitude * PixelIntegratedGaussian(u, stripe_centre, o.stripe_sigma_px);
      const auto value = [&](int channel) {
        const double signal =
            channel == kMono ? laser + scene
                             : laser * o.laser_colour[channel] + scene * o.scene_colour[channel];
        const double noisy = signal + o.noise * gaussian(rng);
        return std::clamp(std::round(noisy * full), 0.0, full);
      };
      if (channels == 3) {
        for (int c = 0; c < 3; ++c) {
          const double x = value(c);
          if (o.sixteen_bit)
            result.image.at<cv::Vec3w>(v, u)[2 - c] = static_cast<uint16_t>(x);
          else
            result.image.at<cv::Vec3b>(v, u)[2 - c] = static_cast<uint8_t>(x);
        }
      } else {
        const double x = value(ColourAt(o.layout, v, u));
        if (o.sixteen_bit)
          result.image.at<uint16_t>(v, u) = static_cast<uint16_t>(x);
        else
          result.image.at<uint8_t>(v, u) = static_cast<uint8_t>(x);
      }
    }
  }
  return result;
}

}  // namespace uwscan::laser
