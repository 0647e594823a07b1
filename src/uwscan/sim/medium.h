// The water body: inherent optical properties (thesis §2.1) as functions of
// wavelength, derived from a single turbidity parameter, the particle beam
// attenuation c_p at 530 nm (1/m).
//
//   a(λ) = a_w(λ) + a_p(530) exp(-S (λ - 530))       pure water + particles/CDOM
//   b(λ) = b_p(530) (530 / λ)                          particle scattering
//   c(λ) = a(λ) + b(λ)                                 Beer–Lambert, eq. 2.1
//
// a_w from Pope & Fry (1997), S = 0.014/nm (Bricaud et al. 1981), the split
// of c_p into a_p and b_p interpolated between Petzold's three measured
// waters (Mobley 1994, Tab. 3.10: clear ocean, coastal ocean, turbid harbour).
// See docs/simulator.md.
#pragma once

#include <Eigen/Core>
#include <string>

namespace uwscan::sim {

// Nominal centre wavelengths of the sensor's R, G, B channels (nm).
inline constexpr double kChannelWavelengthNm[3] = {620.0, 530.0, 450.0};

struct Medium {
  std::string name = "clear";
  bool air = false;  // no water at all (in-air calibration images): no attenuation or scattering
  double particle_attenuation_530 = 0.1003;  // c_p(530) = c - a_w, 1/m; 0 = pure water
  double phase_g = 0.924;           // Henyey–Greenstein asymmetry fitted to Petzold's VSF
  double forward_fraction = 0.5;    // share of b scattered into the small-angle lobe
  double forward_angle_rad = 0.03;  // rms angle of that lobe

  double Absorption(double wavelength_nm) const;
  double Scattering(double wavelength_nm) const;
  double Attenuation(double wavelength_nm) const {
    return Absorption(wavelength_nm) + Scattering(wavelength_nm);
  }
  // Attenuation of light that stays within the forward lobe (sharp + blurred).
  double ForwardTransmissionCoefficient(double wavelength_nm) const {
    return Absorption(wavelength_nm) + (1.0 - forward_fraction) * Scattering(wavelength_nm);
  }
  // Per channel (R, G, B) at kChannelWavelengthNm.
  Eigen::Vector3d AttenuationRgb() const;
  Eigen::Vector3d ScatteringRgb() const;
  // Henyey–Greenstein phase function (1/sr) for the scattering angle cosine.
  double Phase(double cos_angle) const;

  void Check(const std::string& context) const;

  // air | pure | clear | coastal | turbid (alias harbour); throws uwscan::Error.
  static Medium Preset(const std::string& name);
  // A preset name or a number c_p(530) >= 0 in 1/m; throws uwscan::Error.
  static Medium Parse(const std::string& turbidity);
  static Medium FromParticleAttenuation(double particle_attenuation_530);
};

// Pure-water absorption a_w(λ) (1/m), Pope & Fry 1997, linear between table
// entries, 400–700 nm (clamped outside).
double PureWaterAbsorption(double wavelength_nm);

// Relative spectral response (0..1) of the sensor's R, G, B filters at a
// wavelength: Gaussian approximations of a typical Bayer CMOS.
Eigen::Vector3d ChannelResponse(double wavelength_nm);

// Linear interpolation of a per-channel (R, G, B) quantity at a wavelength.
double InterpolateRgb(const Eigen::Vector3d& rgb, double wavelength_nm);

}  // namespace uwscan::sim
