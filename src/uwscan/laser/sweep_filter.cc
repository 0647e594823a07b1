#include "uwscan/laser/sweep_filter.h"

#include <algorithm>
#include <cmath>

#include "uwscan/util/error.h"

namespace uwscan::laser {

void SweepFilterOptions::Check() const {
  UWS_CHECK(focal_px > 0.0 && min_expected_shift_px > 0.0 && max_lag_s > 0.0 &&
                static_tolerance_px >= 0.0 && tolerance_of_shift > 0.0 &&
                tolerance_of_shift < 1.0 && line_search >= 0,
            "sweep filter: invalid options");
}

SweepFilter::SweepFilter(const SweepFilterOptions& options) : options_(options) {
  options_.Check();
}

void SweepFilter::Begin(double timestamp_s, double servo_angle_rad) {
  timestamp_s_ = timestamp_s;
  angle_rad_ = servo_angle_rad;
  while (!history_.empty() && !options_.WithinLag(timestamp_s - history_.front().timestamp_s))
    history_.pop_front();
  references_.clear();
  for (const Past& past : history_) {
    const double shift = options_.focal_px * std::abs(servo_angle_rad - past.angle_rad);
    if (shift >= options_.min_expected_shift_px)
      references_.emplace_back(
          &past, std::max(options_.static_tolerance_px, options_.tolerance_of_shift * shift));
  }
}

bool SweepFilter::IsStatic(double position, int line, bool strict) const {
  for (const auto& [past, shift_tolerance] : references_) {
    const double tolerance = strict ? options_.static_tolerance_px : shift_tolerance;
    const int lo = std::max(line - options_.line_search, past->first_line);
    const int hi = std::min(line + options_.line_search,
                            past->first_line + static_cast<int>(past->line_start.size()) - 2);
    for (int l = lo; l <= hi; ++l) {
      const size_t i = static_cast<size_t>(l - past->first_line);
      for (int k = past->line_start[i]; k < past->line_start[i + 1]; ++k) {
        if (std::abs(past->positions[static_cast<size_t>(k)] - position) <= tolerance) return true;
      }
    }
  }
  return false;
}

void SweepFilter::End(const std::vector<LaserPoint>& candidates) {
  Past now;
  now.timestamp_s = timestamp_s_;
  now.angle_rad = angle_rad_;
  if (!candidates.empty()) {
    const auto line_of = [&](const LaserPoint& p) {
      return static_cast<int>(std::lround(options_.scan_rows ? p.v : p.u));
    };
    int lo = line_of(candidates.front()), hi = lo;
    for (const LaserPoint& p : candidates) {
      const int line = line_of(p);
      lo = std::min(lo, line);
      hi = std::max(hi, line);
    }
    now.first_line = lo;
    std::vector<int> count(static_cast<size_t>(hi - lo + 1), 0);
    for (const LaserPoint& p : candidates) ++count[static_cast<size_t>(line_of(p) - lo)];
    now.line_start.assign(count.size() + 1, 0);
    for (size_t i = 0; i < count.size(); ++i) now.line_start[i + 1] = now.line_start[i] + count[i];
    now.positions.resize(candidates.size());
    std::vector<int> fill(now.line_start.begin(), now.line_start.end() - 1);
    for (const LaserPoint& p : candidates) {
      const size_t i = static_cast<size_t>(line_of(p) - lo);
      now.positions[static_cast<size_t>(fill[i]++)] =
          static_cast<float>(options_.scan_rows ? p.u : p.v);
    }
  } else {
    now.line_start = {0};
  }
  history_.push_back(std::move(now));
  // history_ is a deque: push_back keeps pointers to the other elements,
  // but the references belong to the frame that just ended.
  references_.clear();
}

std::function<bool(double, int)> SweepFilter::Predicate(bool strict) const {
  if (references_.empty()) return {};
  return [this, strict](double position, int line) { return IsStatic(position, line, strict); };
}

}  // namespace uwscan::laser
