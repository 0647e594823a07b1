#include "uwscan/sim/ins.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

namespace uwscan::sim {
namespace {

TEST(Ins, ErrorsFollowTheModel) {
  MotionOptions motion;
  motion.type = MotionType::kHover;
  motion.amplitude_m = 0.02;
  motion.amplitude_rad = 0.01;
  const Trajectory truth(motion);
  InsOptions options;
  options.time_offset_s = 0.0;
  options.heading_random_walk_rad = 0.0;
  options.position_random_walk_m = 0.0;
  const auto ins = SimulateIns(truth, 0.0, 10.0, options);
  ASSERT_EQ(ins.size(), 501u);  // 50 Hz over 10 s
  double position = 0.0, attitude = 0.0;
  for (const auto& pose : ins) {
    const Rigid3d true_pose = truth.WorldFromCamera(pose.timestamp_s);
    position += (pose.world_from_camera.translation - true_pose.translation).squaredNorm();
    attitude += std::pow(
        Eigen::AngleAxisd(pose.world_from_camera.rotation * true_pose.rotation.conjugate()).angle(),
        2);
  }
  // White noise only: RMS per axis as configured (3 axes).
  EXPECT_NEAR(std::sqrt(position / ins.size() / 3.0), options.position_noise_m, 0.15e-3);
  EXPECT_NEAR(std::sqrt(attitude / ins.size() / 3.0), options.attitude_noise_rad, 0.3e-4);

  // The random walk makes the error grow with time.
  InsOptions drifting;
  const auto drift = SimulateIns(truth, 0.0, 100.0, drifting);
  const double early =
      (drift[50].world_from_camera.translation -
       truth.WorldFromCamera(drift[50].timestamp_s - drifting.time_offset_s).translation)
          .norm();
  double late = 0.0;
  for (size_t i = drift.size() - 50; i < drift.size(); ++i) {
    late += (drift[i].world_from_camera.translation -
             truth.WorldFromCamera(drift[i].timestamp_s - drifting.time_offset_s).translation)
                .norm();
  }
  EXPECT_GT(late / 50.0, early);
}

}  // namespace
}  // namespace uwscan::sim
