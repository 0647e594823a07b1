// TUM trajectory files with gaps (io/tum.h has the plain reader/writer): one pose per line `t x y z
// qx qy qz qw` (world_from_camera), '#' comments. uwscan marks tracking gaps with comment lines `#
// gap <t_begin> <t_end> <reason>` so that readers that only know TUM still read the poses.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "uwscan/geometry/rigid3d.h"
#include "uwscan/io/tum.h"  // StampedPose

namespace uwscan {

struct TrajectoryGap {
  double begin_s = 0.0;
  double end_s = 0.0;
  std::string reason;
};

struct TumTrajectory {
  std::vector<StampedPose> poses;
  std::vector<TrajectoryGap> gaps;
};

// Throws uwscan::Error naming the file and line on malformed input.
// Quaternions must be unit to `unit_tolerance` (ReadTum: 1e-6).
TumTrajectory ReadTumTrajectory(const std::filesystem::path& path, double unit_tolerance = 1e-3);
TumTrajectory ParseTumTrajectory(const std::string& text, const std::string& source,
                                 double unit_tolerance = 1e-3);
std::string TumTrajectoryToText(const TumTrajectory& trajectory);
// Atomic write.
void WriteTumTrajectory(const std::filesystem::path& path, const TumTrajectory& trajectory);

}  // namespace uwscan
