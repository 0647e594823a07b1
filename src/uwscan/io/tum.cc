#include "uwscan/io/tum.h"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <sstream>

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
  std::vector<StampedPose> poses;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream fields(line);
    double v[8];
    for (double& value : v) {
      UWS_CHECK(static_cast<bool>(fields >> value), path.string(), ":", number,
                ": expected 8 numbers 't x y z qx qy qz qw'");
    }
    std::string rest;
    UWS_CHECK(!(fields >> rest), path.string(), ":", number, ": more than 8 values");
    const Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
    UWS_CHECK(std::abs(q.norm() - 1.0) < 1e-6, path.string(), ":", number,
              ": quaternion is not unit length");
    // Poses are interpolated between their neighbours in time.
    UWS_CHECK(poses.empty() || v[0] > poses.back().timestamp_s, path.string(), ":", number,
              ": timestamps must increase (", v[0], " after ", poses.back().timestamp_s, ")");
    poses.push_back({v[0], Rigid3d(q, Eigen::Vector3d(v[1], v[2], v[3]))});
  }
  return poses;
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

}  // namespace uwscan
