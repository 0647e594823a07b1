#include "uwscan/sim/medium.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>

#include "uwscan/util/error.h"

namespace uwscan::sim {
namespace {

// Pope & Fry (1997), a_w in 1/m.
constexpr std::array<std::pair<double, double>, 13> kPopeFry = {{{400, 0.00663},
                                                                 {425, 0.00478},
                                                                 {450, 0.00922},
                                                                 {475, 0.0114},
                                                                 {500, 0.0204},
                                                                 {525, 0.0481},
                                                                 {530, 0.0507},
                                                                 {550, 0.0565},
                                                                 {575, 0.0896},
                                                                 {600, 0.2224},
                                                                 {625, 0.2834},
                                                                 {650, 0.3400},
                                                                 {700, 0.6240}}};

constexpr double kCdomSlopePerNm = 0.014;

// Petzold's waters at 530 nm (Mobley 1994, Tab. 3.10): a, b in 1/m.
struct Petzold {
  double a, b;
};
constexpr Petzold kClear{0.114, 0.037};
constexpr Petzold kCoastal{0.179, 0.219};
constexpr Petzold kHarbour{0.366, 1.824};

double ParticleAttenuation(const Petzold& water) {
  return water.a - PureWaterAbsorption(530) + water.b;
}

// Scattering share b_p / c_p, interpolated in log c_p between Petzold's waters.
double ScatteringShare(double particle_attenuation) {
  const std::array<Petzold, 3> waters = {kClear, kCoastal, kHarbour};
  std::array<double, 3> log_c, share;
  for (size_t i = 0; i < waters.size(); ++i) {
    log_c[i] = std::log(ParticleAttenuation(waters[i]));
    share[i] = waters[i].b / ParticleAttenuation(waters[i]);
  }
  if (particle_attenuation <= 0) return share[0];
  const double x = std::log(particle_attenuation);
  if (x <= log_c[0]) return share[0];
  if (x >= log_c[2]) return share[2];
  const size_t i = x < log_c[1] ? 0 : 1;
  const double w = (x - log_c[i]) / (log_c[i + 1] - log_c[i]);
  return share[i] + w * (share[i + 1] - share[i]);
}

}  // namespace

double PureWaterAbsorption(double wavelength_nm) {
  if (wavelength_nm <= kPopeFry.front().first) return kPopeFry.front().second;
  if (wavelength_nm >= kPopeFry.back().first) return kPopeFry.back().second;
  for (size_t i = 1; i < kPopeFry.size(); ++i) {
    if (wavelength_nm <= kPopeFry[i].first) {
      const auto [l0, a0] = kPopeFry[i - 1];
      const auto [l1, a1] = kPopeFry[i];
      return a0 + (a1 - a0) * (wavelength_nm - l0) / (l1 - l0);
    }
  }
  return kPopeFry.back().second;
}

Eigen::Vector3d ChannelResponse(double wavelength_nm) {
  constexpr double kCentre[3] = {610.0, 535.0, 460.0};
  constexpr double kSigma[3] = {45.0, 40.0, 35.0};
  Eigen::Vector3d response;
  for (int k = 0; k < 3; ++k) {
    const double x = (wavelength_nm - kCentre[k]) / kSigma[k];
    response[k] = std::exp(-0.5 * x * x);
  }
  return response;
}

double InterpolateRgb(const Eigen::Vector3d& rgb, double wavelength_nm) {
  // Channels ordered by decreasing wavelength: R 620, G 530, B 450.
  const double* l = kChannelWavelengthNm;
  if (wavelength_nm >= l[0]) return rgb[0];
  if (wavelength_nm <= l[2]) return rgb[2];
  if (wavelength_nm >= l[1])
    return rgb[1] + (rgb[0] - rgb[1]) * (wavelength_nm - l[1]) / (l[0] - l[1]);
  return rgb[2] + (rgb[1] - rgb[2]) * (wavelength_nm - l[2]) / (l[1] - l[2]);
}

double Medium::Absorption(double wavelength_nm) const {
  if (air) return 0.0;
  const double particle_a =
      particle_attenuation_530 * (1.0 - ScatteringShare(particle_attenuation_530));
  return PureWaterAbsorption(wavelength_nm) +
         particle_a * std::exp(-kCdomSlopePerNm * (wavelength_nm - 530.0));
}

double Medium::Scattering(double wavelength_nm) const {
  if (air) return 0.0;
  const double particle_b = particle_attenuation_530 * ScatteringShare(particle_attenuation_530);
  return particle_b * 530.0 / wavelength_nm;
}

Eigen::Vector3d Medium::AttenuationRgb() const {
  return {Attenuation(kChannelWavelengthNm[0]), Attenuation(kChannelWavelengthNm[1]),
          Attenuation(kChannelWavelengthNm[2])};
}

Eigen::Vector3d Medium::ScatteringRgb() const {
  return {Scattering(kChannelWavelengthNm[0]), Scattering(kChannelWavelengthNm[1]),
          Scattering(kChannelWavelengthNm[2])};
}

double Medium::Phase(double cos_angle) const {
  const double g = phase_g;
  const double denominator = 1.0 + g * g - 2.0 * g * cos_angle;
  return (1.0 - g * g) / (4.0 * M_PI * denominator * std::sqrt(denominator));
}

void Medium::Check(const std::string& context) const {
  UWS_CHECK(std::isfinite(particle_attenuation_530) && particle_attenuation_530 >= 0, context,
            ": turbidity (particle attenuation c_p at 530 nm) must be >= 0 1/m (got ",
            particle_attenuation_530, ")");
  UWS_CHECK(particle_attenuation_530 <= 50, context,
            ": turbidity above 50 1/m is outside the model (got ", particle_attenuation_530, ")");
  UWS_CHECK(std::isfinite(phase_g) && phase_g > -1 && phase_g < 1, context,
            ": phase_g must be in (-1, 1)");
  UWS_CHECK(forward_fraction >= 0 && forward_fraction <= 1, context,
            ": forward_fraction must be in [0, 1]");
  UWS_CHECK(std::isfinite(forward_angle_rad) && forward_angle_rad >= 0 && forward_angle_rad < 1,
            context, ": forward_angle_rad must be in [0, 1)");
}

Medium Medium::FromParticleAttenuation(double particle_attenuation_530) {
  Medium medium;
  medium.name = "custom";
  medium.particle_attenuation_530 = particle_attenuation_530;
  medium.Check("medium");
  return medium;
}

Medium Medium::Preset(const std::string& name) {
  Medium medium;
  if (name == "air") {
    medium.air = true;
    medium.particle_attenuation_530 = 0.0;
  } else if (name == "pure") {
    medium.particle_attenuation_530 = 0.0;
  } else if (name == "clear") {
    medium.particle_attenuation_530 = ParticleAttenuation(kClear);
  } else if (name == "coastal") {
    medium.particle_attenuation_530 = ParticleAttenuation(kCoastal);
  } else if (name == "turbid" || name == "harbour") {
    medium.particle_attenuation_530 = ParticleAttenuation(kHarbour);
  } else {
    UWS_THROW("unknown water preset '", name, "' (air, pure, clear, coastal, turbid)");
  }
  medium.name = name == "harbour" ? "turbid" : name;
  return medium;
}

Medium Medium::Parse(const std::string& turbidity) {
  double value = 0.0;
  const auto result = std::from_chars(turbidity.data(), turbidity.data() + turbidity.size(), value);
  if (result.ec == std::errc() && result.ptr == turbidity.data() + turbidity.size()) {
    UWS_CHECK(std::isfinite(value) && value >= 0,
              "--turbidity must be a preset or a number >= 0 "
              "(particle attenuation at 530 nm in 1/m), got '",
              turbidity, "'");
    return FromParticleAttenuation(value);
  }
  return Preset(turbidity);
}

}  // namespace uwscan::sim
