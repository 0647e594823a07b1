// The sparse map of the visual odometry (thesis §5.2): keyframes with their
// feature observations and the 3D points triangulated from them. Only the
// sliding window of keyframes and the points they (or the live tracks) see
// are kept, so memory stays constant over long sequences.
#pragma once

#include <cstdint>
#include <deque>
#include <optional>
#include <unordered_map>
#include <vector>

#include "uwscan/geometry/rigid3d.h"

namespace uwscan::vo {

// A laser range measurement for the windowed bundle adjustment (thesis §5.4,
// scale equalisation): the map point `point_id`, seen in the frame the
// constraint comes with, lies at `range_m` along its ray from the ray origin
// (outer port surface, Camera::BackProject), with standard deviation sigma_m.
struct RangeConstraint {
  uint64_t point_id = 0;
  double range_m = 0.0;
  double sigma_m = 0.001;
  // The ray's origin (camera frame) when the keyframe has no observation of
  // the point to take it from: a point where the laser line crosses it is
  // masked for tracking (thesis §5.4, the map point meeting the line).
  std::optional<Eigen::Vector3d> ray_origin_camera = std::nullopt;
};

struct MapPoint {
  uint64_t id = 0;  // equals the id of the feature track it came from
  Eigen::Vector3d position_world = Eigen::Vector3d::Zero();
  int num_observations = 0;  // in keyframes of the window
};

struct Keyframe {
  uint64_t id = 0;  // running keyframe number
  int frame_index = 0;
  double timestamp_s = 0.0;
  Rigid3d camera_from_world;
  std::unordered_map<uint64_t, Eigen::Vector2d> observations;  // track id -> pixel
  std::vector<RangeConstraint> range_constraints;
  Rigid3d WorldFromCamera() const { return camera_from_world.Inverse(); }
};

struct SparseMap {
  std::deque<Keyframe> keyframes;  // oldest first; the BA window is the tail
  std::unordered_map<uint64_t, MapPoint> points;

  void Clear() {
    keyframes.clear();
    points.clear();
  }
  const MapPoint* FindPoint(uint64_t id) const {
    const auto it = points.find(id);
    return it == points.end() ? nullptr : &it->second;
  }
};

}  // namespace uwscan::vo
