#include "uwscan/io/tum_trajectory.h"

#include <cstdio>
#include <fstream>
#include <sstream>

#include "uwscan/io/timestamps.h"
#include "uwscan/util/atomic_file.h"
#include "uwscan/util/csv.h"
#include "uwscan/util/error.h"

namespace uwscan {

TumTrajectory ParseTumTrajectory(const std::string& text, const std::string& source,
                                 double unit_tolerance) {
  TumTrajectory trajectory;
  std::istringstream in(text);
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    if (++line_number == 1) StripByteOrderMark(line);
    const size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos) continue;
    if (line[first] == '#') {
      std::istringstream comment(line.substr(first + 1));
      std::string word;
      TrajectoryGap gap;
      if (comment >> word && word == "gap" && comment >> gap.begin_s >> gap.end_s) {
        std::getline(comment >> std::ws, gap.reason);
        trajectory.gaps.push_back(gap);
      }
      continue;
    }
    // A CSV (EuRoC's ground truth: nanoseconds, then qw before qx) read
    // as TUM failed with "expected 8 numbers" and no hint.
    UWS_CHECK(line.find(',') == std::string::npos, source, ":", line_number,
              ": commas: a TUM trajectory's fields `t x y z qx qy qz qw` are separated by "
              "spaces (a CSV trajectory such as EuRoC's, in nanoseconds and with qw first, "
              "converts with `evo_traj euroc FILE --save_as_tum`)");
    std::istringstream fields(line);
    double v[8];
    for (double& value : v) {
      UWS_CHECK(fields >> value, source, ":", line_number,
                ": expected 8 numbers `t x y z qx qy qz qw`");
    }
    std::string rest;
    UWS_CHECK(!(fields >> rest), source, ":", line_number, ": more than 8 fields");
    const Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
    UWS_CHECK(std::abs(q.norm() - 1.0) < unit_tolerance, source, ":", line_number,
              ": quaternion is not unit (norm ", q.norm(), ")");
    // Poses are associated with the truth's and interpolated in time.
    UWS_CHECK(trajectory.poses.empty() || v[0] > trajectory.poses.back().timestamp_s, source, ":",
              line_number, ": timestamps must increase (", v[0], " after ",
              trajectory.poses.back().timestamp_s, ")");
    trajectory.poses.push_back({v[0], Rigid3d(q, Eigen::Vector3d(v[1], v[2], v[3]))});
  }
  std::vector<double> times;
  for (const StampedPose& pose : trajectory.poses) times.push_back(pose.timestamp_s);
  CheckTimestampsInSeconds(times, source);
  return trajectory;
}

TumTrajectory ReadTumTrajectory(const std::filesystem::path& path, double unit_tolerance) {
  std::ifstream in(path);
  UWS_CHECK(in, path.string(), ": cannot open trajectory");
  std::stringstream buffer;
  buffer << in.rdbuf();
  return ParseTumTrajectory(buffer.str(), path.string(), unit_tolerance);
}

std::string TumTrajectoryToText(const TumTrajectory& trajectory) {
  std::string out = "# uwscan trajectory: t x y z qx qy qz qw (world_from_camera)\n";
  char buffer[256];
  for (const TrajectoryGap& gap : trajectory.gaps) {
    std::snprintf(buffer, sizeof(buffer), "# gap %.9f %.9f ", gap.begin_s, gap.end_s);
    out += buffer + gap.reason + "\n";
  }
  for (const StampedPose& pose : trajectory.poses) {
    const Eigen::Quaterniond& q = pose.world_from_camera.rotation;
    const Eigen::Vector3d& t = pose.world_from_camera.translation;
    std::snprintf(buffer, sizeof(buffer), "%.9f %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n",
                  pose.timestamp_s, t.x() + 0.0, t.y() + 0.0, t.z() + 0.0, q.x() + 0.0, q.y() + 0.0,
                  q.z() + 0.0, q.w() + 0.0);  // + 0.0: no "-0"
    out += buffer;
  }
  return out;
}

void WriteTumTrajectory(const std::filesystem::path& path, const TumTrajectory& trajectory) {
  WriteFileAtomic(path, TumTrajectoryToText(trajectory));
}

}  // namespace uwscan
