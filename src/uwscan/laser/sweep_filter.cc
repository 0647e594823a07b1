#include "uwscan/laser/sweep_filter.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "uwscan/util/error.h"

namespace uwscan::laser {

void SweepFilterOptions::Check() const {
  UWS_CHECK(focal_px > 0.0 && min_expected_shift_px > 0.0 && max_lag_frames >= 1 &&
                static_tolerance_px >= 0.0 && restore_fraction > 0.0 && restore_fraction <= 1.0 &&
                line_search >= 0,
            "sweep filter: invalid options");
}

float SweepFilter::Past::At(int line) const {
  const int i = line - first_line;
  return i >= 0 && i < static_cast<int>(position_by_line.size())
             ? position_by_line[static_cast<size_t>(i)]
             : std::numeric_limits<float>::quiet_NaN();
}

SweepFilter::SweepFilter(const SweepFilterOptions& options) : options_(options) {
  options_.Check();
}

std::vector<LaserPoint> SweepFilter::Filter(int frame, double servo_angle_rad,
                                            const std::vector<LaserPoint>& points, int* removed) {
  *removed = 0;
  const auto line_of = [&](const LaserPoint& p) {
    return static_cast<int>(std::lround(options_.scan_rows ? p.v : p.u));
  };
  const auto across = [&](const LaserPoint& p) { return options_.scan_rows ? p.u : p.v; };
  while (!history_.empty() && frame - history_.front().frame > options_.max_lag_frames)
    history_.pop_front();
  // The frames the sheet has turned far enough from since.
  std::vector<std::pair<const Past*, double>> references;  // frame, tolerance
  for (const Past& past : history_) {
    const double shift = options_.focal_px * std::abs(servo_angle_rad - past.angle_rad);
    if (shift >= options_.min_expected_shift_px)
      references.emplace_back(&past, std::max(options_.static_tolerance_px, 0.25 * shift));
  }
  Past now{frame, servo_angle_rad, 0, {}};
  if (!points.empty()) {
    int lo = line_of(points.front()), hi = lo;
    for (const LaserPoint& p : points) lo = std::min(lo, line_of(p)), hi = std::max(hi, line_of(p));
    now.first_line = lo;
    now.position_by_line.assign(static_cast<size_t>(hi - lo + 1),
                                std::numeric_limits<float>::quiet_NaN());
    for (const LaserPoint& p : points)
      now.position_by_line[static_cast<size_t>(line_of(p) - lo)] = static_cast<float>(across(p));
  }
  std::vector<LaserPoint> kept;
  for (const LaserPoint& p : points) {
    // Found at the same place (neighbouring scan lines too: a stripe is not
    // found on every line of every frame) in any of those frames?
    bool stayed = false;
    const int own_line = line_of(p);
    const float position = across(p);
    for (const auto& [past, tolerance] : references) {
      for (int line = own_line - options_.line_search;
           line <= own_line + options_.line_search && !stayed; ++line) {
        stayed = std::abs(past->At(line) - position) <= tolerance;  // false for NaN
      }
      if (stayed) break;
    }
    if (!stayed) kept.push_back(p);
  }
  history_.push_back(std::move(now));
  if (references.empty() || kept.size() == points.size() ||
      points.size() - kept.size() > options_.restore_fraction * points.size()) {
    return points;
  }
  *removed = static_cast<int>(points.size() - kept.size());
  return kept;
}

}  // namespace uwscan::laser
