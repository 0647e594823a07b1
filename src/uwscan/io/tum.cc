#include "uwscan/io/tum.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "uwscan/io/tum_trajectory.h"
#include "uwscan/util/error.h"

namespace uwscan {

std::string TumLine(const StampedPose& pose) {
  const Eigen::Vector3d& t = pose.world_from_camera.translation;
  const Eigen::Quaterniond& q = pose.world_from_camera.rotation;
  return fmt::format("{:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g}\n",
                     pose.timestamp_s, t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w());
}

std::vector<StampedPose> ReadTum(const std::filesystem::path& path) {
  std::ifstream in(path);
  UWS_CHECK(in.good(), path.string(), ": cannot open for reading");
  std::stringstream text;
  text << in.rdbuf();
  // Gap comments are comments here; quaternions unit to 1e-6.
  return ParseTumTrajectory(text.str(), path.string(), 1e-6).poses;
}

void WriteTum(const std::filesystem::path& path, const std::vector<StampedPose>& poses) {
  TumWriter writer(path);
  for (const auto& pose : poses) writer.Add(pose);
  writer.Commit();
}

TumWriter::TumWriter(const std::filesystem::path& path) : file_(path) {
  file_.stream() << "# timestamp x y z qx qy qz qw (world_from_camera)\n";
}

void TumWriter::Add(const StampedPose& pose) { file_.stream() << TumLine(pose); }

const StampedPose* NearestInTime(const std::vector<StampedPose>& by_time, double timestamp_s,
                                 double max_dt_s) {
  const auto after =
      std::lower_bound(by_time.begin(), by_time.end(), timestamp_s,
                       [](const StampedPose& pose, double t) { return pose.timestamp_s < t; });
  const StampedPose* nearest = nullptr;
  double nearest_dt = max_dt_s;
  for (auto candidate : {after, after == by_time.begin() ? after : after - 1}) {
    if (candidate == by_time.end()) continue;
    const double dt = std::abs(candidate->timestamp_s - timestamp_s);
    if (dt <= nearest_dt) nearest_dt = dt, nearest = &*candidate;
  }
  return nearest;
}

}  // namespace uwscan
