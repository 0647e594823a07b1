// Light sources of the simulator. Lasers and floods are fixed to the rig and
// expressed in the frame of the first camera.
//
// A line laser (thesis §5.3) emits `power_w` spread uniformly over its fan
// angle along the line, with a Gaussian cross-section whose 1/e^2 full width
// grows linearly with range: w(r) = width_m + divergence_rad * r. Its sheet is
// the model of eq. 4.30 (rig.yaml's camera_from_laser and p1). An optional
// servo turns the laser about `servo_axis` (laser frame, through
// `servo_pivot`): camera_from_laser(angle) = camera_from_laser(0) * R(axis, angle).
#pragma once

#include <Eigen/Core>
#include <string>

#include "uwscan/geometry/rigid3d.h"

namespace uwscan::sim {

struct LaserSource {
  int rig_laser = 0;              // index into Rig::lasers (pose, p1, wavelength)
  double power_w = 0.1;           // optical power on the line
  double fan_angle_rad = 1.0;     // full fan angle along the line
  double width_m = 0.002;         // 1/e^2 full width at the exit
  double divergence_rad = 0.002;  // full-angle growth of the width
  bool servo = false;
  Eigen::Vector3d servo_axis = Eigen::Vector3d::UnitX();  // laser frame, unit
  Eigen::Vector3d servo_pivot = Eigen::Vector3d::Zero();  // laser frame (m)

  // Laser frame at `angle` -> laser frame at angle 0.
  Rigid3d ServoRotation(double angle_rad) const;
  void Check(const std::string& context) const;
};

// A flood light (the red LED of §6.4): radiant intensity
// I(θ) = I0 cos^m θ about its z axis, I0 = power_w (m + 1) / (2π).
struct FloodLight {
  std::string name = "led0";
  Rigid3d camera_from_light;  // light z axis = beam axis
  double power_w = 2.0;       // radiant power
  double wavelength_nm = 630.0;
  double exponent = 2.0;  // m of the cos^m beam pattern

  double Intensity(double cos_angle) const;  // W/sr
  void Check(const std::string& context) const;
};

// Diffuse light from a uniform upper hemisphere (world +z): irradiance per
// channel on an upward-facing surface (W/m^2 per band), E (1 + cos tilt) / 2
// on a tilted one; zero for night or tank work.
struct Ambient {
  Eigen::Vector3d irradiance_rgb = Eigen::Vector3d::Zero();
  void Check(const std::string& context) const;
};

}  // namespace uwscan::sim
