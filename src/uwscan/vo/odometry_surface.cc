// Odometry with an active sensor's surface (fusion, thesis §5.4): map
// points from the measured surface at keyframes (and measured again where
// the depth was only extrapolated), and the map started from the surface.
#include <algorithm>
#include <chrono>
#include <cmath>

#include "uwscan/util/error.h"
#include "uwscan/util/stopwatch.h"
#include "uwscan/vo/odometry.h"

namespace uwscan::vo {

bool Odometry::ExtrapolatedDepthAgrees(const Keyframe& keyframe, uint64_t id,
                                       const Eigen::Vector3d& point_world) const {
  if (!(options_.max_extrapolated_disagreement_px > 0)) return true;
  if (map_.keyframes.empty() ||
      static_cast<int>(map_.points.size()) < options_.min_map_points_to_defer) {
    return true;  // starting the map: every depth counts
  }
  int seen_before = 0;
  for (const Keyframe& kf : map_.keyframes) {
    if (kf.id == keyframe.id) continue;
    const auto seen = kf.observations.find(id);
    if (seen == kf.observations.end()) continue;
    ++seen_before;
    const auto projected = camera_.Project(kf.camera_from_world * point_world, options_.ba.method,
                                           options_.ba.taylor_iterations);
    if (!projected ||
        (*projected - seen->second).norm() > options_.max_extrapolated_disagreement_px)
      return false;
  }
  return seen_before > 0;  // first seen now: wait for the next keyframe
}

void Odometry::MovePoint(MapPoint* point, const Eigen::Vector3d& position_world) {
  point->position_world = position_world;
  // The constraints that held it where it was go with it.
  for (Keyframe& kf : map_.keyframes) {
    auto& ranges = kf.range_constraints;
    ranges.erase(
        std::remove_if(ranges.begin(), ranges.end(),
                       [id = point->id](const RangeConstraint& r) { return r.point_id == id; }),
        ranges.end());
  }
}

int Odometry::AddSurfacePoints(Keyframe* keyframe) {
  const Rigid3d world_from_camera = keyframe->WorldFromCamera();
  int added = 0;
  for (const auto& [id, pixel] : keyframe->observations) {
    const auto existing = map_.points.find(id);
    const bool remeasure = existing != map_.points.end() && extrapolated_points_.count(id) > 0;
    if (existing != map_.points.end() && !remeasure) continue;
    const auto ray = camera_.BackProject(pixel);
    if (!ray) continue;
    const Ray world = ray->Transformed(world_from_camera);
    const auto hit = options_.surface(world.origin, world.direction);
    if (!hit) continue;
    if (remeasure) {
      const bool provisional = provisional_points_.count(id) > 0;
      if (hit->extrapolated && (!provisional || hit->provisional)) continue;  // not swept yet
      provisional_points_.erase(id);
      if (hit->extrapolated) {
        // The surface it was extrapolated from has settled (a plane on a
        // band grown wide enough): its depth from the provisional one is
        // not kept at all (BENCHMARKS.md, "Points from the start's narrow
        // plane placed again once it settles").
        MovePoint(&existing->second, hit->point_world);
        ++provisional_placed_again_;
      } else {
        // Measured now. A point far from the measurement sat on the wrong
        // surface (e.g. a shaft in front of the extrapolated hull): move it
        // and drop the constraints that held it there.
        extrapolated_points_.erase(id);
        const double range = (existing->second.position_world - world.origin).norm();
        const double measured = (hit->point_world - world.origin).norm();
        if (std::abs(range - measured) > 3.0 * hit->sigma_m) {
          MovePoint(&existing->second, hit->point_world);
          ++remeasured_moved_;
        }
      }
    } else {
      if (hit->extrapolated && !ExtrapolatedDepthAgrees(*keyframe, id, hit->point_world)) continue;
      map_.points[id] = {id, hit->point_world, 1};
      if (hit->extrapolated) extrapolated_points_.insert(id);
      if (hit->extrapolated && hit->provisional) provisional_points_.insert(id);
    }
    keyframe->range_constraints.push_back(
        {id, (hit->point_world - world.origin).norm(), hit->sigma_m});
    ++added;
  }
  return added;
}

FrameResult Odometry::InitializeFromSurface(const cv::Mat& image, const cv::Mat& mask,
                                            double timestamp_s, const Rigid3d& world_from_camera) {
  UWS_CHECK(static_cast<bool>(options_.surface), "vo: InitializeFromSurface needs options.surface");
  const auto start = std::chrono::steady_clock::now();
  FrameResult result;
  result.frame_index = frame_count_++;
  result.timestamp_s = timestamp_s;
  result.status = FrameStatus::kInitializing;
  const cv::Mat gray = ToGray8(image);
  if (gray.empty() || gray.cols != camera_.width || gray.rows != camera_.height) {
    result.status = FrameStatus::kInvalid;
    result.message = "invalid image for initialisation";
    return result;
  }
  UWS_CHECK(mask.empty() || (mask.type() == CV_8UC1 && mask.size() == gray.size()),
            "vo: mask must be empty or CV_8U of the image size");
  timestamp_s_ = timestamp_s;
  tracker_.Reset();
  result.tracking = tracker_.Track(gray, mask);
  tracker_.Detect(mask, &result.tracking);
  MoveTracksToTruth();
  tracker_.SetAnchor(mask);
  MergeBundleAdjustment(&result);  // an earlier map's BA in flight, if any
  SparseMap previous = std::move(map_);
  map_.Clear();
  Keyframe keyframe;
  keyframe.id = next_keyframe_id_;
  keyframe.frame_index = result.frame_index;
  keyframe.timestamp_s = timestamp_s;
  keyframe.camera_from_world = world_from_camera.Inverse();
  for (const auto& t : tracker_.tracks()) keyframe.observations[t.id] = t.pixel;
  const int points = AddSurfacePoints(&keyframe);
  if (points < options_.min_pnp_inliers) {
    map_ = std::move(previous);
    result.message = "surface initialisation: " + std::to_string(points) +
                     " features with a measured depth (need " +
                     std::to_string(options_.min_pnp_inliers) + ")";
    result.total_time_s = SecondsSince(start);
    return result;
  }
  map_.keyframes.push_back(std::move(keyframe));
  ++next_keyframe_id_;
  ++num_maps_;
  state_ = State::kTracking;
  reference_.reset();
  result.status = FrameStatus::kTracked;
  result.message = "initialised from the measured surface";
  result.keyframe = true;
  result.world_from_camera = world_from_camera;
  result.map_matches = result.inliers = points;
  last_keyframe_inliers_ = points;
  last_camera_from_world_ = world_from_camera.Inverse();
  last_median_depth_ = MedianDepth(map_.keyframes.back());
  result.total_time_s = SecondsSince(start);
  return result;
}

}  // namespace uwscan::vo
