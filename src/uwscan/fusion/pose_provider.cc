#include "uwscan/fusion/pose_provider.h"

#include <algorithm>
#include <cmath>

#include "uwscan/util/error.h"

namespace uwscan::fusion {

std::optional<Rigid3d> InterpolatePose(const std::vector<StampedPose>& poses, double t,
                                       double max_extrapolation_s) {
  if (poses.empty()) return std::nullopt;
  const auto after =
      std::lower_bound(poses.begin(), poses.end(), t,
                       [](const StampedPose& p, double time) { return p.timestamp_s < time; });
  if (after == poses.begin()) {
    if (poses.front().timestamp_s - t > max_extrapolation_s) return std::nullopt;
    return poses.front().world_from_camera;
  }
  if (after == poses.end()) {
    if (t - poses.back().timestamp_s > max_extrapolation_s) return std::nullopt;
    return poses.back().world_from_camera;
  }
  const StampedPose& a = *(after - 1);
  const StampedPose& b = *after;
  const double span = b.timestamp_s - a.timestamp_s;
  const double w = span > 0 ? (t - a.timestamp_s) / span : 0.0;
  return Rigid3d(a.world_from_camera.rotation.slerp(w, b.world_from_camera.rotation),
                 (1.0 - w) * a.world_from_camera.translation + w * b.world_from_camera.translation);
}

std::optional<PoseChange> RmsPoseChange(const std::vector<std::optional<Rigid3d>>& before,
                                        const std::vector<std::optional<Rigid3d>>& after) {
  double moved = 0.0, turned = 0.0;
  int count = 0;
  for (size_t i = 0; i < std::min(before.size(), after.size()); ++i) {
    if (!before[i] || !after[i]) continue;
    const Rigid3d change = before[i]->Inverse() * *after[i];
    moved += change.translation.squaredNorm();
    const double angle = Eigen::AngleAxisd(change.rotation).angle();
    turned += angle * angle;
    ++count;
  }
  if (count == 0) return std::nullopt;
  return PoseChange{std::sqrt(moved / count), std::sqrt(turned / count) * 180.0 / M_PI};
}

TrajectoryPoseProvider::TrajectoryPoseProvider(std::vector<StampedPose> poses, std::string name,
                                               double max_extrapolation_s,
                                               std::vector<std::pair<double, double>> gaps)
    : poses_(std::move(poses)),
      name_(std::move(name)),
      max_extrapolation_s_(max_extrapolation_s),
      gaps_(std::move(gaps)) {
  UWS_CHECK(!poses_.empty(), name_, ": the trajectory has no poses");
  std::stable_sort(poses_.begin(), poses_.end(), [](const StampedPose& a, const StampedPose& b) {
    return a.timestamp_s < b.timestamp_s;
  });
}

std::vector<PoseUpdate> TrajectoryPoseProvider::Add(const FrameInput& frame) {
  for (const auto& [begin, end] : gaps_) {
    if (frame.timestamp_s > begin && frame.timestamp_s < end) return {};
  }
  const auto pose = InterpolatePose(poses_, frame.timestamp_s, max_extrapolation_s_);
  if (!pose) return {};
  return {{frame.index, *pose}};
}

}  // namespace uwscan::fusion
