#include "uwscan/laser/sweep_filter.h"

#include <cmath>

#include "uwscan/util/error.h"

namespace uwscan::laser {

void SweepFilterOptions::Check() const {
  UWS_CHECK(focal_px > 0.0 && min_expected_shift_px > 0.0 && max_lag_frames >= 1 &&
                static_tolerance_px >= 0.0 && restore_fraction > 0.0 && restore_fraction <= 1.0 &&
                line_search >= 0,
            "sweep filter: invalid options");
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
  Past now{frame, servo_angle_rad, {}};
  for (const LaserPoint& p : points) now.position_by_line[line_of(p)] = across(p);
  std::vector<LaserPoint> kept;
  for (const LaserPoint& p : points) {
    // Found at the same place (neighbouring scan lines too: a stripe is not
    // found on every line of every frame) in any of those frames?
    bool stayed = false;
    for (const auto& [past, tolerance] : references) {
      for (int line = line_of(p) - options_.line_search;
           line <= line_of(p) + options_.line_search && !stayed; ++line) {
        const auto then = past->position_by_line.find(line);
        stayed = then != past->position_by_line.end() && std::abs(then->second - across(p)) <= tolerance;
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
