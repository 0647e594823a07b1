// Detector options: method, channel and colour-layout names, and the
// options' checks (the detection itself is in detector.cc).
#include <string>

#include "uwscan/laser/detector.h"
#include "uwscan/util/error.h"

namespace uwscan::laser {

std::optional<Method> MethodFromName(const std::string& name) {
  if (name == "thesis") return Method::kThesis;
  if (name == "cog") return Method::kCentreOfGravity;
  if (name == "argmax") return Method::kArgmax;
  return std::nullopt;
}

const char* MethodName(Method method) {
  switch (method) {
    case Method::kThesis:
      return "thesis";
    case Method::kCentreOfGravity:
      return "cog";
    default:
      return "argmax";
  }
}

const char* ChannelName(int channel) {
  static const char* names[] = {"red", "green", "blue", "mono"};
  return channel >= 0 && channel <= 3 ? names[channel] : "unknown";
}

int ChannelForWavelength(double wavelength_nm) {
  if (wavelength_nm < 490.0) return kBlue;
  if (wavelength_nm < 580.0) return kGreen;
  return kRed;
}

ColourLayout LayoutFor(const std::string& bayer, int image_channels) {
  if (image_channels == 3) return ColourLayout::kBgr;
  UWS_CHECK(image_channels == 1, "laser detection: images must have 1 or 3 channels, not ",
            image_channels);
  if (bayer == "rggb") return ColourLayout::kBayerRggb;
  if (bayer == "bggr") return ColourLayout::kBayerBggr;
  if (bayer == "grbg") return ColourLayout::kBayerGrbg;
  if (bayer == "gbrg") return ColourLayout::kBayerGbrg;
  return ColourLayout::kMono;
}

int ChannelFromName(const std::string& name) {
  if (name == "red") return kRed;
  if (name == "green") return kGreen;
  if (name == "blue") return kBlue;
  return -1;
}

int AlbedoChannelFor(int laser_channel) {
  if (laser_channel == kGreen) return kRed;
  if (laser_channel == kRed || laser_channel == kBlue) return kGreen;
  return -1;
}

int SignatureChannelFor(int laser_channel) {
  if (laser_channel == kGreen || laser_channel == kRed) return kBlue;
  if (laser_channel == kBlue) return kRed;
  return -1;
}

void DetectorOptions::Check() const {
  UWS_CHECK(line_sigma_px > kMinLineSigmaPx && line_sigma_px < kMaxLineSigmaPx,
            "laser detection: line sigma must be ", kMinLineSigmaPx, "-", kMaxLineSigmaPx, " px");
  UWS_CHECK(min_snr >= 0.0 && min_strength >= 0.0 && min_contrast >= 0.0,
            "laser detection: thresholds must be >= 0");
  UWS_CHECK(noise_half_window_px >= 2, "laser detection: noise window must be >= 2 px");
  UWS_CHECK(max_jump_px >= 1 && max_gap_lines >= 0 && min_segment_lines >= 1,
            "laser detection: invalid connectivity settings");
  UWS_CHECK(min_relative_strength >= 0.0 && min_relative_strength <= 1.0,
            "laser detection: relative segment strength must be in [0, 1]");
  UWS_CHECK(line_continuity_px >= 0.0, "laser detection: line continuity must be >= 0 px");
  UWS_CHECK(cog_threshold > 0.0 && cog_threshold < 1.0,
            "laser detection: cog threshold must be in (0, 1)");
  UWS_CHECK(laser_channel >= kRed && laser_channel <= kMono, "laser detection: invalid channel");
  UWS_CHECK(albedo_channel >= -1 && albedo_channel <= kBlue,
            "laser detection: invalid albedo channel");
  UWS_CHECK(min_albedo_reference >= 0.0 && max_albedo_step > 1.0,
            "laser detection: albedo step must be > 1");
  UWS_CHECK(line_window_px >= 1, "laser detection: line window must be >= 1 px");
  UWS_CHECK(min_signature_share >= 0.0 && min_signature_share < 1.0 && min_signature_height >= 0.0,
            "laser detection: colour signature share must be in [0, 1), its height >= 0");
}

}  // namespace uwscan::laser
