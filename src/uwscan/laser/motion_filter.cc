#include "uwscan/laser/motion_filter.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "uwscan/util/error.h"

namespace uwscan::laser {

void MotionFilterOptions::Check() const {
  UWS_CHECK(min_shift_px > 0.0 && max_lag_frames >= 1 && tolerance_px >= 0.0 &&
                tolerance_of_shift >= 0.0 && tolerance_of_shift < 0.5 && line_search >= 0 &&
                depth_search_lines >= 0 && max_prediction_frames >= 1,
            "motion filter: invalid options");
}

MotionFilter::MotionFilter(const Camera& camera, const MotionFilterOptions& options)
    : camera_(camera), options_(options) {
  options_.Check();
}

std::optional<Rigid3d> MotionFilter::PredictPose(double timestamp_s) const {
  // The two latest frames with a pose, recent enough.
  const Past* b = nullptr;
  const Past* a = nullptr;
  for (auto it = history_.rbegin(); it != history_.rend(); ++it) {
    if (frame_ - it->frame > options_.max_prediction_frames + 1) break;
    if (!it->world_from_camera) continue;
    if (!b) {
      b = &*it;
    } else {
      a = &*it;
      break;
    }
  }
  if (!a || !b || frame_ - b->frame > options_.max_prediction_frames) return std::nullopt;
  const double span = b->timestamp_s - a->timestamp_s;
  if (!(span > 0.0)) return std::nullopt;
  const double w = (timestamp_s - b->timestamp_s) / span;
  const Rigid3d& pa = *a->world_from_camera;
  const Rigid3d& pb = *b->world_from_camera;
  const Eigen::AngleAxisd step(pb.rotation * pa.rotation.inverse());
  const Eigen::Quaterniond rotation =
      Eigen::Quaterniond(Eigen::AngleAxisd(w * step.angle(), step.axis())) * pb.rotation;
  return Rigid3d(rotation.normalized(), pb.translation + w * (pb.translation - pa.translation));
}

void MotionFilter::Begin(int frame, double timestamp_s) {
  frame_ = frame;
  timestamp_s_ = timestamp_s;
  while (!history_.empty() &&
         frame - history_.front().frame >
             std::max(options_.max_lag_frames, options_.max_prediction_frames + 1)) {
    history_.pop_front();
  }
  references_.clear();
  const int lines = options_.scan_rows ? camera_.height : camera_.width;
  moved_.resize(static_cast<size_t>(lines));
  for (auto& on_line : moved_) on_line.clear();  // keeps their memory from frame to frame
  const std::optional<Rigid3d> world_from_camera = PredictPose(timestamp_s);
  if (!world_from_camera) return;
  const Rigid3d camera_from_world = world_from_camera->Inverse();
  std::vector<std::pair<int, Moved>> moved;
  std::vector<double> shifts;
  for (const Past& past : history_) {
    if (!past.world_from_camera || frame - past.frame > options_.max_lag_frames ||
        past.points.empty()) {
      continue;
    }
    const Rigid3d now_from_past = camera_from_world * *past.world_from_camera;
    moved.clear();
    shifts.clear();
    for (size_t i = 0; i < past.points.size(); ++i) {
      const auto pixel = camera_.Project(now_from_past * past.points[i], ProjectionMethod::kTaylor);
      if (!pixel) continue;
      const double line = options_.scan_rows ? pixel->y() : pixel->x();
      const double position = options_.scan_rows ? pixel->x() : pixel->y();
      const int l = static_cast<int>(std::lround(line));
      if (l < 0 || l >= lines) continue;
      shifts.push_back(std::abs(position - past.positions[i]));
      moved.push_back({l, {static_cast<float>(position), 0.0f}});
    }
    if (shifts.size() < 10) continue;
    auto middle = shifts.begin() + static_cast<long>(shifts.size() / 2);
    std::nth_element(shifts.begin(), middle, shifts.end());
    const double shift = *middle;
    if (shift < options_.min_shift_px) continue;  // the scene has hardly moved across the line
    const float tolerance =
        static_cast<float>(std::max(options_.tolerance_px, options_.tolerance_of_shift * shift));
    for (auto& [line, m] : moved) {
      m.tolerance = tolerance;
      moved_[static_cast<size_t>(line)].push_back(m);
    }
    references_.push_back(past.frame);
  }
}

bool MotionFilter::MovesWithScene(double position, int line, bool strict) const {
  if (references_.empty()) return false;
  const int lo = std::max(0, line - options_.line_search);
  const int hi = std::min(static_cast<int>(moved_.size()) - 1, line + options_.line_search);
  for (int l = lo; l <= hi; ++l) {
    for (const Moved& m : moved_[static_cast<size_t>(l)]) {
      const double tolerance = strict ? options_.tolerance_px : m.tolerance;
      if (std::abs(m.position - position) <= tolerance) return true;
    }
  }
  return false;
}

std::function<bool(double, int)> MotionFilter::Predicate(bool strict) const {
  if (references_.empty()) return {};
  return
      [this, strict](double position, int line) { return MovesWithScene(position, line, strict); };
}

void MotionFilter::End(const std::vector<LaserPoint>& candidates, const Profile& profile) {
  Past now;
  now.frame = frame_;
  now.timestamp_s = timestamp_s_;
  // Depth (camera z) of the profile per scan line; a candidate takes the
  // median of those within depth_search_lines.
  std::vector<std::pair<double, double>> depth_by_line;  // line, z
  for (const ProfilePoint& p : profile.points) {
    depth_by_line.emplace_back(options_.scan_rows ? p.pixel.y() : p.pixel.x(),
                               p.point_in_camera.z());
  }
  std::sort(depth_by_line.begin(), depth_by_line.end());
  std::vector<double> nearby;
  for (const LaserPoint& candidate : candidates) {
    const double line = options_.scan_rows ? candidate.v : candidate.u;
    const auto first = std::lower_bound(depth_by_line.begin(), depth_by_line.end(),
                                        std::make_pair(line - options_.depth_search_lines, -1e300));
    nearby.clear();
    for (auto it = first;
         it != depth_by_line.end() && it->first <= line + options_.depth_search_lines; ++it) {
      nearby.push_back(it->second);
    }
    if (nearby.size() < 3) continue;
    auto middle = nearby.begin() + static_cast<long>(nearby.size() / 2);
    std::nth_element(nearby.begin(), middle, nearby.end());
    const double depth = *middle;
    const auto ray = camera_.BackProject({candidate.u, candidate.v});
    if (!ray || std::abs(ray->direction.z()) < 1e-9) continue;
    const double s = (depth - ray->origin.z()) / ray->direction.z();
    if (!(s > 0.0)) continue;
    now.points.push_back(ray->origin + s * ray->direction);
    now.positions.push_back(static_cast<float>(options_.scan_rows ? candidate.u : candidate.v));
  }
  history_.push_back(std::move(now));
  references_.clear();  // they belonged to the frame that just ended
}

void MotionFilter::SetPose(int frame, const Rigid3d& world_from_camera) {
  for (Past& past : history_) {
    if (past.frame == frame) past.world_from_camera = world_from_camera;
  }
}

}  // namespace uwscan::laser
