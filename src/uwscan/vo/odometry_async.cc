// Odometry: the windowed bundle adjustment on a second thread. The BA works
// on a copy of the window (keyframes and the points they see); tracking
// goes on against the map as it was, and the adjusted poses, points and
// outlier decisions are merged a fixed number of frames later
// (OdometryOptions::async_merge_frames), at the latest before the next
// keyframe's BA starts, so at most one is in flight.
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
  frames_since_ba_launch_ = 0;
  pending_ba_ = std::async(std::launch::async, [camera = camera_, options = options_.ba,
                                                window = std::move(window)]() mutable {
    AdjustedWindow result;
    result.summary = AdjustWindow(camera, options, &window);
    result.window = std::move(window);
    return result;
  });
}

void Odometry::MergeBundleAdjustment(FrameResult* result) {
  if (!pending_ba_.valid()) return;
  AdjustedWindow adjusted = pending_ba_.get();
  for (Keyframe& kf : adjusted.window.keyframes) {
    for (Keyframe& live : map_.keyframes) {
      if (live.id != kf.id) continue;
      live.camera_from_world = kf.camera_from_world;
      // Observations the BA found to be outliers, range constraints it
      // removed (a keyframe's constraints are fixed when it is made).
      for (auto it = live.observations.begin(); it != live.observations.end();) {
        it = kf.observations.count(it->first) ? std::next(it) : live.observations.erase(it);
      }
      live.range_constraints = std::move(kf.range_constraints);
    }
  }
  for (const auto& [id, point] : adjusted.window.points) {
    const auto it = map_.points.find(id);
    if (it != map_.points.end()) it->second.position_world = point.position_world;
  }
  ApplyRemovedObservations(adjusted.summary.removed_observations);
  if (result) result->bundle_adjustment = std::move(adjusted.summary);
}

void Odometry::DiscardBundleAdjustment() {
  if (pending_ba_.valid()) pending_ba_.wait();
  pending_ba_ = {};
}

}  // namespace uwscan::vo
