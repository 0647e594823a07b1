#include "uwscan/sim/ins.h"

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "uwscan/util/error.h"

namespace uwscan::sim {

void InsOptions::Check() const {
  UWS_CHECK(rate_hz > 0 && position_noise_m >= 0 && position_random_walk_m >= 0 &&
                attitude_noise_rad >= 0 && heading_random_walk_rad >= 0,
            "INS: rates and noise levels must be positive");
}

std::vector<StampedPose> SimulateIns(const Trajectory& truth, double start_s, double end_s,
                                     const InsOptions& options) {
  options.Check();
  UWS_CHECK(end_s >= start_s, "INS: end before start");
  std::mt19937_64 rng(options.seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  const double dt = 1.0 / options.rate_hz;
  Eigen::Vector3d walk = Eigen::Vector3d::Zero();
  double heading = 0.0;
  std::vector<StampedPose> poses;
  for (double t = start_s; t <= end_s + 0.5 * dt; t += dt) {
    walk += options.position_random_walk_m * std::sqrt(dt) *
            Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
    heading += options.heading_random_walk_rad * std::sqrt(dt) * normal(rng);
    const Rigid3d pose = truth.WorldFromCamera(t - options.time_offset_s);
    const Eigen::Vector3d attitude_error =
        options.attitude_noise_rad * Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
    // Heading drifts about the world vertical, noise about the body axes.
    const Eigen::Quaterniond rotation =
        Eigen::Quaterniond(Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitZ())) * pose.rotation *
        Eigen::Quaterniond(Eigen::AngleAxisd(
            attitude_error.norm(),
            attitude_error.norm() > 0 ? attitude_error.normalized() : Eigen::Vector3d::UnitX()));
    const Eigen::Vector3d position =
        pose.translation + walk +
        options.position_noise_m * Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
    poses.push_back({t, Rigid3d(rotation.normalized(), position)});
  }
  return poses;
}

}  // namespace uwscan::sim
