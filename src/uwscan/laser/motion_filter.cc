#include "uwscan/laser/motion_filter.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "uwscan/sensor/triangulation.h"
#include "uwscan/util/error.h"

namespace uwscan::laser {

void MotionFilterOptions::Check() const {
  UWS_CHECK(min_shift_px > 0.0 && max_lag_frames >= 1 && tolerance_px >= 0.0 &&
                tolerance_of_shift >= 0.0 && tolerance_of_shift < 0.5 && line_search >= 0 &&
                depth_search_lines >= 0 && max_prediction_frames >= 1,
            "motion filter: invalid options");
  UWS_CHECK(epipolar_lag_frames >= 1 && epipolar_tolerance_px > 0.0 && epipolar_samples >= 2 &&
                near_factor > 0.0 && near_factor <= 1.0 && far_factor >= 1.0 &&
                min_parallax_px >= 0.0,
            "motion filter: invalid epipolar options");
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
  const int keep =
      std::max(options_.max_lag_frames + (options_.epipolar ? options_.epipolar_lag_frames : 0),
               options_.max_prediction_frames + 1);
  while (!history_.empty() && frame - history_.front().frame > keep) history_.pop_front();
  references_.clear();
  epipolar_matches_ = 0;
  const int lines = options_.scan_rows ? camera_.height : camera_.width;
  moved_.resize(static_cast<size_t>(lines));
  for (auto& on_line : moved_) on_line.clear();  // keeps their memory from frame to frame
  const std::optional<Rigid3d> world_from_camera = PredictPose(timestamp_s);
  if (!world_from_camera) return;
  const Rigid3d camera_from_world = world_from_camera->Inverse();
  std::vector<std::pair<int, Moved>> moved;
  std::vector<double> shifts;
  for (Past& past : history_) {
    if (!past.world_from_camera || frame - past.frame > options_.max_lag_frames ||
        past.points.empty()) {
      continue;
    }
    if (options_.epipolar && !past.epipolar_done) MatchEpipolar(&past);
    const Rigid3d now_from_past = camera_from_world * *past.world_from_camera;
    moved.clear();
    shifts.clear();
    int matches = 0;
    for (size_t i = 0; i < past.points.size(); ++i) {
      if (!past.points[i].allFinite()) continue;
      const auto pixel = camera_.Project(now_from_past * past.points[i], ProjectionMethod::kTaylor);
      if (!pixel) continue;
      const double line = options_.scan_rows ? pixel->y() : pixel->x();
      const double position = options_.scan_rows ? pixel->x() : pixel->y();
      const int l = static_cast<int>(std::lround(line));
      if (l < 0 || l >= lines) continue;
      const double was = options_.scan_rows ? past.pixels[i].x() : past.pixels[i].y();
      shifts.push_back(std::abs(position - was));
      moved.push_back({l, {static_cast<float>(position), 0.0f}});
      matches += past.matched[i];
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
    epipolar_matches_ += matches;
  }
}

void MotionFilter::MatchEpipolar(Past* past) {
  // The earliest earlier frame with a pose: the widest baseline.
  const Past* earlier = nullptr;
  for (const Past& e : history_) {
    if (e.frame >= past->frame) break;
    if (past->frame - e.frame > options_.epipolar_lag_frames || !e.world_from_camera ||
        e.pixels.empty()) {
      continue;
    }
    earlier = &e;
    break;
  }
  if (!earlier) return;  // perhaps later, once its pose is known
  past->epipolar_done = true;
  const double near_m = options_.near_factor * std::min(past->min_depth_m, earlier->min_depth_m);
  const double far_m = options_.far_factor * std::max(past->max_depth_m, earlier->max_depth_m);
  if (!(near_m > 0.0) || !(far_m > near_m)) return;
  const Rigid3d earlier_from_past =
      earlier->world_from_camera->Inverse() * *past->world_from_camera;
  for (size_t i = 0; i < past->pixels.size(); ++i) {
    if (!past->rays[i]) continue;
    const auto point = MatchAlongCurve(*past->rays[i], earlier_from_past, *earlier, near_m, far_m);
    if (!point) continue;
    past->points[i] = *point;
    past->matched[i] = 1;
    ++epipolar_matches_total_;
  }
}

std::optional<Eigen::Vector3d> MotionFilter::MatchAlongCurve(const Ray& ray,
                                                             const Rigid3d& earlier_from_past,
                                                             const Past& earlier, double near_m,
                                                             double far_m) const {
  if (ray.direction.z() < 1e-6) return std::nullopt;
  const auto along = [&](double depth_m) { return (depth_m - ray.origin.z()) / ray.direction.z(); };
  // (position across the line, scan line) of a point of `past` in `earlier`.
  const auto in_earlier = [&](const Eigen::Vector3d& point) -> std::optional<Eigen::Vector2d> {
    const auto pixel = camera_.Project(earlier_from_past * point, ProjectionMethod::kTaylor);
    if (!pixel) return std::nullopt;
    return options_.scan_rows ? *pixel : Eigen::Vector2d(pixel->y(), pixel->x());
  };
  const auto far_end = in_earlier(ray.At(1e4));
  if (!far_end) return std::nullopt;
  const double tolerance = options_.epipolar_tolerance_px;
  int match = -1;
  std::optional<Eigen::Vector2d> previous;
  for (int k = 0; k < options_.epipolar_samples; ++k) {
    // Even steps in inverse depth: even steps along the curve.
    const double w =
        1.0 / far_m + (1.0 / near_m - 1.0 / far_m) * k / (options_.epipolar_samples - 1);
    const auto current = in_earlier(ray.At(along(1.0 / w)));
    if (current && previous) {
      const Eigen::Vector2d a = *previous, ab = *current - *previous;
      const double length2 = std::max(ab.squaredNorm(), 1e-12);
      const int first = static_cast<int>(std::floor(std::min(a.y(), current->y()) - tolerance));
      const int last = static_cast<int>(std::ceil(std::max(a.y(), current->y()) + tolerance));
      auto it = std::lower_bound(earlier.by_line.begin(), earlier.by_line.end(),
                                 std::make_pair(first, -1));
      for (; it != earlier.by_line.end() && it->first <= last; ++it) {
        const int index = it->second;
        const Eigen::Vector2d& pixel = earlier.pixels[static_cast<size_t>(index)];
        const Eigen::Vector2d c =
            options_.scan_rows ? pixel : Eigen::Vector2d(pixel.y(), pixel.x());
        const double t = std::clamp((c - a).dot(ab) / length2, 0.0, 1.0);
        if ((a + t * ab - c).norm() > tolerance) continue;
        if ((c - *far_end).norm() < options_.min_parallax_px) continue;  // depth not measured
        if (match >= 0 && match != index) return std::nullopt;           // ambiguous
        match = index;
      }
    }
    previous = current;
  }
  if (match < 0) return std::nullopt;
  const auto& other = earlier.rays[static_cast<size_t>(match)];
  if (!other) return std::nullopt;
  const auto point = TriangulateRays({ray, other->Transformed(earlier_from_past.Inverse())});
  if (!point || point->z() < near_m || point->z() > far_m) return std::nullopt;
  return point;
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
  now.min_depth_m = std::numeric_limits<double>::infinity();
  for (const ProfilePoint& p : profile.points) {
    const double z = p.point_in_camera.z();
    depth_by_line.emplace_back(options_.scan_rows ? p.pixel.y() : p.pixel.x(), z);
    now.min_depth_m = std::min(now.min_depth_m, z);
    now.max_depth_m = std::max(now.max_depth_m, z);
  }
  if (profile.points.empty()) now.min_depth_m = 0.0;
  std::sort(depth_by_line.begin(), depth_by_line.end());
  std::vector<double> nearby;
  const Eigen::Vector3d unknown =
      Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  for (const LaserPoint& candidate : candidates) {
    const double line = options_.scan_rows ? candidate.v : candidate.u;
    now.by_line.emplace_back(static_cast<int>(std::lround(line)),
                             static_cast<int>(now.pixels.size()));
    now.pixels.emplace_back(candidate.u, candidate.v);
    now.rays.push_back(camera_.BackProject(now.pixels.back()));
    now.points.push_back(unknown);
    now.matched.push_back(0);
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
    const auto& ray = now.rays.back();
    if (!ray || std::abs(ray->direction.z()) < 1e-9) continue;
    const double s = (depth - ray->origin.z()) / ray->direction.z();
    if (!(s > 0.0)) continue;
    now.points.back() = ray->origin + s * ray->direction;
  }
  std::sort(now.by_line.begin(), now.by_line.end());
  history_.push_back(std::move(now));
  references_.clear();  // they belonged to the frame that just ended
}

void MotionFilter::SetPose(int frame, const Rigid3d& world_from_camera) {
  for (Past& past : history_) {
    if (past.frame == frame) past.world_from_camera = world_from_camera;
  }
}

}  // namespace uwscan::laser
