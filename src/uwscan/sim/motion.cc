#include "uwscan/sim/motion.h"

#include <Eigen/Geometry>
#include <cmath>

#include "uwscan/sim/random.h"
#include "uwscan/util/error.h"

namespace uwscan::sim {

const char* MotionTypeName(MotionType type) {
  switch (type) {
    case MotionType::kStatic:
      return "static";
    case MotionType::kHover:
      return "hover";
    case MotionType::kTransect:
      return "transect";
    case MotionType::kViews:
      return "views";
  }
  return "static";
}

MotionType MotionTypeFromName(const std::string& name, const std::string& context) {
  if (name == "static") return MotionType::kStatic;
  if (name == "hover") return MotionType::kHover;
  if (name == "transect") return MotionType::kTransect;
  if (name == "views") return MotionType::kViews;
  UWS_THROW(context, ": motion type must be static, hover, transect or views (got '", name, "')");
}

void MotionOptions::Check(const std::string& context) const {
  UWS_CHECK(std::isfinite(amplitude_m) && amplitude_m >= 0, context,
            ": motion amplitude must be >= 0 (got ", amplitude_m, ")");
  UWS_CHECK(std::isfinite(amplitude_rad) && amplitude_rad >= 0 && amplitude_rad < 0.5, context,
            ": rotation amplitude must be in [0, 0.5) rad");
  UWS_CHECK(std::isfinite(bandwidth_hz) && bandwidth_hz > 0, context,
            ": bandwidth must be positive");
  UWS_CHECK(velocity_world.allFinite(), context, ": velocity must be finite");
}

Trajectory::Trajectory(const MotionOptions& options) : options_(options) {
  options_.Check("motion");
  Rng rng(StreamSeed(options.seed, 0x307104));
  for (auto& axis : axes_) {
    for (int k = 0; k < kComponents; ++k) {
      // Band-limited: frequencies spread over [0.1, 1] x bandwidth.
      axis.frequency_hz[k] = options.bandwidth_hz * rng.Uniform(0.1, 1.0);
      axis.phase_rad[k] = rng.Uniform(0.0, 2 * M_PI);
    }
  }
}

double Trajectory::Offset(const Axis& axis, double amplitude, double time_s) const {
  // Sum of K sinusoids of amplitude A sqrt(2/K): rms A.
  const double each = amplitude * std::sqrt(2.0 / kComponents);
  double sum = 0.0;
  for (int k = 0; k < kComponents; ++k) {
    sum += each * std::sin(2 * M_PI * axis.frequency_hz[k] * time_s + axis.phase_rad[k]);
  }
  return sum;
}

Rigid3d Trajectory::WorldFromCamera(double time_s) const {
  const Rigid3d& start = options_.world_from_camera_start;
  if (options_.type == MotionType::kStatic || options_.type == MotionType::kViews) return start;
  Eigen::Vector3d translation = start.translation;
  if (options_.type == MotionType::kTransect) translation += options_.velocity_world * time_s;
  Eigen::Vector3d rotation_vector;
  for (int i = 0; i < 3; ++i) {
    translation[i] += Offset(axes_[i], options_.amplitude_m, time_s);
    rotation_vector[i] = Offset(axes_[3 + i], options_.amplitude_rad, time_s);
  }
  const double angle = rotation_vector.norm();
  const Eigen::Quaterniond wobble =
      angle > 0 ? Eigen::Quaterniond(Eigen::AngleAxisd(angle, rotation_vector / angle))
                : Eigen::Quaterniond::Identity();
  return Rigid3d(start.rotation * wobble, translation);
}

}  // namespace uwscan::sim
