#include "uwscan/sim/sensor_model.h"

#include <algorithm>
#include <cmath>

#include "uwscan/sim/parallel.h"
#include "uwscan/sim/random.h"
#include "uwscan/util/error.h"

namespace uwscan::sim {

const char* OutputFormatName(OutputFormat format) {
  switch (format) {
    case OutputFormat::kBayer:
      return "bayer";
    case OutputFormat::kRgb:
      return "rgb";
    case OutputFormat::kMono:
      return "mono";
  }
  return "bayer";
}

OutputFormat OutputFormatFromName(const std::string& name) {
  if (name == "bayer") return OutputFormat::kBayer;
  if (name == "rgb") return OutputFormat::kRgb;
  if (name == "mono") return OutputFormat::kMono;
  UWS_THROW("output must be bayer, rgb or mono (got '", name, "')");
}

double SensorOptions::ElectronsPerRadiance(double wavelength_nm) const {
  constexpr double kPlanckTimesLight = 1.98644586e-25;  // h c in J m
  const double photons_per_joule = wavelength_nm * 1e-9 / kPlanckTimesLight;
  return M_PI / (4.0 * f_number * f_number) * pixel_pitch_m * pixel_pitch_m * exposure_s *
         quantum_efficiency * photons_per_joule;
}

void SensorOptions::Check(const std::string& context) const {
  UWS_CHECK(std::isfinite(exposure_s) && exposure_s > 0, context, ": exposure must be positive");
  UWS_CHECK(std::isfinite(f_number) && f_number > 0, context, ": f_number must be positive");
  UWS_CHECK(std::isfinite(pixel_pitch_m) && pixel_pitch_m > 0, context,
            ": pixel pitch must be positive");
  UWS_CHECK(quantum_efficiency > 0 && quantum_efficiency <= 1, context,
            ": quantum efficiency must be in (0, 1]");
  UWS_CHECK(std::isfinite(full_well_e) && full_well_e > 0, context, ": full well must be positive");
  UWS_CHECK(std::isfinite(read_noise_e) && read_noise_e >= 0, context, ": read noise must be >= 0");
  UWS_CHECK(std::isfinite(gain) && gain >= 1 && gain <= 1000, context, ": gain must be in 1..1000");
  UWS_CHECK(bits == 8 || bits == 12 || bits == 16, context, ": bits must be 8, 12 or 16 (got ",
            bits, ")");
}

int BayerChannel(const std::string& bayer, int x, int y) {
  // Pattern string names the 2x2 cell row by row: e.g. rggb = R G / G B.
  const char c = bayer[(y & 1) * 2 + (x & 1)];
  return c == 'r' ? 0 : (c == 'g' ? 1 : 2);
}

cv::Mat Digitize(const cv::Mat& electrons_rgb, const SensorOptions& options,
                 const std::string& bayer, uint64_t seed, int threads) {
  UWS_CHECK(electrons_rgb.type() == CV_32FC3, "Digitize: expects CV_32FC3 electrons");
  const bool mosaic = options.output == OutputFormat::kBayer;
  UWS_CHECK(!mosaic || bayer.size() == 4, "Digitize: Bayer output needs a pattern (rggb, ...)");
  const int rows = electrons_rgb.rows, cols = electrons_rgb.cols;
  const int channels = options.output == OutputFormat::kRgb ? 3 : 1;
  const bool wide = options.bits > 8;
  cv::Mat image(rows, cols, CV_MAKETYPE(wide ? CV_16U : CV_8U, channels));
  const double max_code = (1 << options.bits) - 1;
  const double gain = options.gain * max_code / options.full_well_e;  // DN per electron
  const double scale_to_container = wide ? (65535.0 + 1) / (max_code + 1) : 1.0;
  const double container_max = wide ? 65535.0 : 255.0;

  // Shot noise (variance = signal, Gaussian approximation of Poisson) and
  // read noise are independent Gaussians: one draw with the summed variance.
  const double read_variance = options.read_noise_e * options.read_noise_e;
  auto sample = [&](double electrons, Rng& rng) {
    double e = std::max(0.0, electrons);
    if (options.noise) e += std::sqrt(e + read_variance) * rng.Normal();
    e = std::min(e, options.full_well_e);
    const double code = std::clamp(std::floor(e * gain + 0.5), 0.0, max_code);
    return std::min(code * scale_to_container, container_max);
  };

  ParallelRows(rows, threads, [&](int y) {
    Rng rng(StreamSeed(seed, 0x5E45, static_cast<uint64_t>(y)));
    const cv::Vec3f* in = electrons_rgb.ptr<cv::Vec3f>(y);
    for (int x = 0; x < cols; ++x) {
      const cv::Vec3f& e = in[x];
      if (channels == 3) {
        // OpenCV stores B G R.
        for (int k = 0; k < 3; ++k) {
          const double value = sample(e[2 - k], rng);
          if (wide)
            image.ptr<uint16_t>(y)[3 * x + k] = static_cast<uint16_t>(value);
          else
            image.ptr<uint8_t>(y)[3 * x + k] = static_cast<uint8_t>(value);
        }
        continue;
      }
      const double electrons =
          mosaic ? e[BayerChannel(bayer, x, y)] : static_cast<double>(e[0] + e[1] + e[2]);
      const double value = sample(electrons, rng);
      if (wide)
        image.ptr<uint16_t>(y)[x] = static_cast<uint16_t>(value);
      else
        image.ptr<uint8_t>(y)[x] = static_cast<uint8_t>(value);
    }
  });
  return image;
}

}  // namespace uwscan::sim
