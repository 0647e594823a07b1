// Platform motion: a static tripod, an ROV hovering with band-limited random
// 6-DoF micro-motion, or a straight transect (with the same micro-motion on
// top). Poses are continuous functions of time, so motion blur can sample
// within the exposure.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>

#include "uwscan/geometry/rigid3d.h"

namespace uwscan::sim {

// kViews: a list of poses (calibration views), kept by the Scenario and
// in groundtruth.tum; the trajectory itself is then static.
enum class MotionType { kStatic, kHover, kTransect, kViews };
const char* MotionTypeName(MotionType type);
MotionType MotionTypeFromName(const std::string& name, const std::string& context);

struct MotionOptions {
  MotionType type = MotionType::kHover;
  Rigid3d world_from_camera_start;
  Eigen::Vector3d velocity_world = Eigen::Vector3d::Zero();  // transect (m/s)
  double amplitude_m = 0.02;     // rms translation per axis (hover, transect)
  double amplitude_rad = 0.005;  // rms rotation per axis
  double bandwidth_hz = 0.5;     // highest frequency of the micro-motion
  uint64_t seed = 1;

  void Check(const std::string& context) const;
};

class Trajectory {
 public:
  explicit Trajectory(const MotionOptions& options);
  Rigid3d WorldFromCamera(double time_s) const;
  const MotionOptions& options() const { return options_; }

 private:
  static constexpr int kComponents = 4;
  struct Axis {
    std::array<double, kComponents> frequency_hz, phase_rad;
  };
  double Offset(const Axis& axis, double amplitude, double time_s) const;

  MotionOptions options_;
  std::array<Axis, 6> axes_;  // tx ty tz (world), rx ry rz (camera frame)
};

}  // namespace uwscan::sim
