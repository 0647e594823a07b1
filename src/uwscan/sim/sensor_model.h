// Image sensor (thesis §2.3, eq. 2.5; §5.3 Bayer filter): radiance in front
// of the port -> electrons through the camera equation, then shot noise
// (Gaussian approximation of Poisson), read noise, gain to full scale at the
// full-well capacity, quantisation to 8/12/16 bit, and optionally an RGGB-type
// Bayer mosaic.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <string>

namespace uwscan::sim {

enum class OutputFormat { kBayer, kRgb, kMono };
const char* OutputFormatName(OutputFormat format);
OutputFormat OutputFormatFromName(const std::string& name);  // throws uwscan::Error

struct SensorOptions {
  double exposure_s = 0.00694;  // thesis §6.4: 144 Hz, 6.94 ms
  double f_number = 2.8;
  double pixel_pitch_m = 3.75e-6;  // Quad-VGA sensor at 1280 px width
  double quantum_efficiency = 0.5;
  double full_well_e = 10000.0;
  double read_noise_e = 5.0;
  double gain = 1.0;  // analog gain: full scale at full_well_e / gain
  int bits = 8;       // 8 | 12 | 16 (12 is stored MSB-aligned in 16 bit)
  OutputFormat output = OutputFormat::kBayer;
  bool noise = true;

  // Electrons per (W m^-2 sr^-1) of radiance at the sensor for light of this
  // wavelength: camera equation E = L π / (4 N^2), times pixel area,
  // exposure, quantum efficiency and photons per joule.
  double ElectronsPerRadiance(double wavelength_nm) const;
  void Check(const std::string& context) const;
};

// Electrons (CV_32FC3, R G B) -> the stored image: for kBayer a one-channel
// mosaic laid out by `bayer` (rggb | bggr | grbg | gbrg), for kRgb a
// three-channel image in OpenCV's B G R order, for kMono the sum of the
// channels. Noise streams are seeded from (seed, row): the result does not
// depend on threads.
cv::Mat Digitize(const cv::Mat& electrons_rgb, const SensorOptions& options,
                 const std::string& bayer, uint64_t seed, int threads = 1);

// Channel (0 = R, 1 = G, 2 = B) sampled at pixel (x, y) of a Bayer pattern.
int BayerChannel(const std::string& bayer, int x, int y);

}  // namespace uwscan::sim
