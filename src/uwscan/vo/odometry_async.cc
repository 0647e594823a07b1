// Odometry: the windowed bundle adjustment on a second thread. The BA works
// on a copy of the window (keyframes and the points they see); tracking
// goes on against the map as it was, and the adjusted poses, points and
// outlier decisions are merged when the BA is done (at the latest before
// the next keyframe's BA starts, so at most one is in flight).
#include <chrono>

#include "uwscan/vo/odometry.h"

namespace uwscan::vo {

void Odometry::LaunchBundleAdjustment() {
  SparseMap window;
  const int first = std::max(0, int(map_.keyframes.size()) - options_.ba.KeyframesRead());
  for (int k = first; k < int(map_.keyframes.size()); ++k) {
    const Keyframe& kf = map_.keyframes[size_t(k)];
    window.keyframes.push_back(kf);
    for (const auto& [id, pixel] : kf.observations) {
      const auto it = map_.points.find(id);
      if (it != map_.points.end()) window.points.emplace(id, it->second);
    }
  }
  pending_ba_ = std::async(std::launch::async, [camera = camera_, options = options_.ba,
                                                window = std::move(window)]() mutable {
    AdjustedWindow result;
    result.summary = AdjustWindow(camera, options, &window);
    result.window = std::move(window);
    return result;
  });
}

bool Odometry::MergeBundleAdjustment(bool wait) {
  if (!pending_ba_.valid()) return false;
  if (!wait && pending_ba_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) {
    return false;
  }
  AdjustedWindow adjusted = pending_ba_.get();
  for (const Keyframe& kf : adjusted.window.keyframes) {
    for (Keyframe& live : map_.keyframes) {
      if (live.id != kf.id) continue;
      live.camera_from_world = kf.camera_from_world;
      // Observations the BA found to be outliers.
      for (auto it = live.observations.begin(); it != live.observations.end();) {
        it = kf.observations.count(it->first) ? std::next(it) : live.observations.erase(it);
      }
    }
  }
  for (const auto& [id, point] : adjusted.window.points) {
    const auto it = map_.points.find(id);
    if (it != map_.points.end()) it->second.position_world = point.position_world;
  }
  ApplyRemovedObservations(adjusted.summary.removed_observations);
  return true;
}

void Odometry::DiscardBundleAdjustment() {
  if (pending_ba_.valid()) pending_ba_.wait();
  pending_ba_ = {};
}

}  // namespace uwscan::vo
