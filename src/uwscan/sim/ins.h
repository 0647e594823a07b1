// A simulated inertial navigation system (thesis §6.5: a fibre-optic-gyro
// INS aided by a DVL, logged at 50 Hz), for comparing the self-referenced
// motion compensation with what a vehicle's navigation would give.
// The error model follows the usual INS datasheet terms: white noise on
// position and attitude, a random walk on position (velocity error) and a
// slowly drifting heading, and a small time offset between camera and INS.
#pragma once

#include <cstdint>
#include <vector>

#include "uwscan/io/tum.h"
#include "uwscan/sim/motion.h"

namespace uwscan::sim {

struct InsOptions {
  double rate_hz = 50.0;
  double position_noise_m = 0.001;          // white, per sample
  double position_random_walk_m = 0.003;    // per sqrt(second)
  double attitude_noise_rad = 0.0002;       // white, per axis (0.01 deg)
  double heading_random_walk_rad = 0.0005;  // per sqrt(second)
  double time_offset_s = 0.002;             // INS stamps late by this
  uint64_t seed = 1;
  void Check() const;
};

// INS poses (world_from_camera, the lever arm is taken as calibrated) over
// [start_s, end_s] of the true trajectory.
std::vector<StampedPose> SimulateIns(const Trajectory& truth, double start_s, double end_s,
                                     const InsOptions& options = {});

}  // namespace uwscan::sim
