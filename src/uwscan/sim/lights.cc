#include "uwscan/sim/lights.h"

#include <Eigen/Geometry>
#include <cmath>

#include "uwscan/util/error.h"

namespace uwscan::sim {

Rigid3d LaserSource::ServoRotation(double angle_rad) const {
  const Eigen::Quaterniond rotation(Eigen::AngleAxisd(angle_rad, servo_axis.normalized()));
  // Rotation about the pivot: x -> R (x - p) + p.
  return Rigid3d(rotation, servo_pivot - rotation * servo_pivot);
}

void LaserSource::Check(const std::string& context) const {
  UWS_CHECK(rig_laser >= 0, context, ": laser index must be >= 0");
  UWS_CHECK(std::isfinite(power_w) && power_w >= 0, context, ": power_w must be >= 0 (got ",
            power_w, ")");
  UWS_CHECK(std::isfinite(fan_angle_rad) && fan_angle_rad > 0 && fan_angle_rad < 3.0, context,
            ": fan_angle_rad must be in (0, 3)");
  UWS_CHECK(std::isfinite(width_m) && width_m > 0, context, ": width_m must be positive");
  UWS_CHECK(std::isfinite(divergence_rad) && divergence_rad >= 0, context,
            ": divergence_rad must be >= 0");
  UWS_CHECK(servo_axis.allFinite() && servo_axis.norm() > 0.5, context,
            ": servo_axis must be a unit vector");
  UWS_CHECK(servo_pivot.allFinite(), context, ": servo_pivot must be finite");
}

double FloodLight::Intensity(double cos_angle) const {
  if (cos_angle <= 0) return 0.0;
  const double peak = power_w * (exponent + 1) / (2 * M_PI);
  if (exponent == 1.5) return peak * cos_angle * std::sqrt(cos_angle);  // the default, off pow()
  return peak * std::pow(cos_angle, exponent);
}

void FloodLight::Check(const std::string& context) const {
  UWS_CHECK(std::isfinite(power_w) && power_w >= 0, context, ": power_w must be >= 0");
  UWS_CHECK(std::isfinite(exponent) && exponent >= 0, context, ": exponent must be >= 0");
  UWS_CHECK(std::isfinite(wavelength_nm) && wavelength_nm >= 350 && wavelength_nm <= 1000, context,
            ": wavelength_nm must be in 350..1000");
}

void Ambient::Check(const std::string& context) const {
  UWS_CHECK(irradiance_rgb.allFinite() && irradiance_rgb.minCoeff() >= 0, context,
            ": ambient irradiance must be >= 0");
}

}  // namespace uwscan::sim
