#include "uwscan/laser/segments.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace uwscan::laser {

std::vector<Segment> GroupPeaks(const std::vector<Peak>& peaks, int max_jump, int max_gap) {
  std::vector<Segment> segments;
  // Open segments: index of the segment and its last peak.
  struct Open {
    int segment;
    int last_peak;
  };
  std::vector<Open> open;
  size_t begin = 0;
  while (begin < peaks.size()) {
    const int line = peaks[begin].line;
    size_t end = begin;
    while (end < peaks.size() && peaks[end].line == line) ++end;
    // Close segments that fell too far behind.
    open.erase(
        std::remove_if(open.begin(), open.end(),
                       [&](const Open& o) { return line - peaks[o.last_peak].line > max_gap + 1; }),
        open.end());
    // Greedy assignment by distance: the closest (segment, peak) pairs join
    // first, each segment and each peak at most once. The reach grows slowly
    // over skipped lines.
    std::vector<bool> taken(end - begin, false);
    struct Candidate {
      double distance;
      int open;
      int peak;
    };
    std::vector<Candidate> candidates;
    for (size_t o = 0; o < open.size(); ++o) {
      const Peak& last = peaks[open[o].last_peak];
      const double reach = max_jump * (1.0 + 0.5 * (line - last.line - 1));
      for (size_t i = begin; i < end; ++i) {
        const double distance = std::abs(peaks[i].position - last.position);
        if (distance <= reach)
          candidates.push_back({distance, static_cast<int>(o), static_cast<int>(i)});
      }
    }
    std::sort(candidates.begin(), candidates.end(),
              [](const Candidate& a, const Candidate& b) { return a.distance < b.distance; });
    std::vector<bool> open_used(open.size(), false);
    for (const auto& c : candidates) {
      if (open_used[c.open] || taken[c.peak - begin]) continue;
      open_used[c.open] = true;
      taken[c.peak - begin] = true;
      segments[open[c.open].segment].peaks.push_back(c.peak);
      open[c.open].last_peak = c.peak;
    }
    for (size_t i = begin; i < end; ++i) {
      if (taken[i - begin]) continue;
      segments.push_back(Segment{{static_cast<int>(i)}, 0.0});
      open.push_back({static_cast<int>(segments.size()) - 1, static_cast<int>(i)});
    }
    begin = end;
  }
  for (auto& segment : segments) {
    double sum = 0.0;
    for (int p : segment.peaks) sum += peaks[p].strength;
    segment.score = segment.peaks.size() + 1e4 * sum;  // eq. 5.1
  }
  return segments;
}

std::vector<std::pair<int, int>> SelectSegments(const std::vector<Peak>& peaks,
                                                const std::vector<Segment>& segments,
                                                int line_count, int min_lines,
                                                double min_relative_strength,
                                                double continuity_px) {
  std::vector<int> order(segments.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return segments[a].score > segments[b].score; });
  // Each segment's mean strength, once (the continuity rounds ask again).
  std::vector<double> mean_strength(segments.size());
  for (size_t s = 0; s < segments.size(); ++s) {
    double sum = 0.0;
    for (int p : segments[s].peaks) sum += peaks[p].strength;
    mean_strength[s] = sum / segments[s].peaks.size();
  }
  // Position of the line taken on each scan line (NaN: none yet).
  std::vector<double> taken_at(line_count, std::numeric_limits<double>::quiet_NaN());
  const auto taken = [&](int line) { return !std::isnan(taken_at[line]); };
  // Whether the end `end` continues the line taken nearest to it in
  // direction `step` (-1 before, +1 after): within continuity_px plus a
  // pixel per scan line between them.
  const auto continues_at = [&](const Peak& end, int step) {
    for (int line = end.line + step; line >= 0 && line < line_count; line += step) {
      if (taken(line))
        return std::abs(taken_at[line] - end.position) <= continuity_px + std::abs(line - end.line);
    }
    return false;
  };
  const auto continues_line = [&](const Segment& segment) {
    return continues_at(peaks[segment.peaks.front()], -1) ||
           continues_at(peaks[segment.peaks.back()], +1);
  };
  std::vector<bool> used(segments.size(), false);
  std::vector<std::pair<int, int>> selected;
  double reference = -1.0;  // mean strength of the best selected segment
  const auto take = [&](int s, bool must_continue) {
    const auto& segment = segments[s];
    if (used[s] || static_cast<int>(segment.peaks.size()) < min_lines) return false;
    if (reference > 0.0 && mean_strength[s] < min_relative_strength * reference) return false;
    int free_lines = 0;
    for (int p : segment.peaks) free_lines += !taken(peaks[p].line);
    if (free_lines < min_lines) return false;
    if (must_continue && !continues_line(segment)) return false;
    if (reference < 0.0) reference = mean_strength[s];
    used[s] = true;
    for (int p : segment.peaks) {
      if (taken(peaks[p].line)) continue;
      taken_at[peaks[p].line] = peaks[p].position;
      selected.emplace_back(p, s);
    }
    return true;
  };
  // The best segment; then, while any is left, those that continue the
  // line taken so far, by score, so that a piece of the line broken off by
  // dark texture keeps its scan lines against a brighter blob beside it
  // (marine snow lit by the floods); then any, by score, on the scan lines
  // still free (a shaft in front of a hull, a second surface).
  for (int s : order) {
    if (take(s, false)) break;
  }
  if (continuity_px > 0.0) {
    for (bool more = true; more;) {
      more = false;
      for (int s : order) more = take(s, true) || more;
    }
  }
  for (int s : order) take(s, false);
  std::sort(selected.begin(), selected.end(), [&](const auto& a, const auto& b) {
    return peaks[a.first].line < peaks[b.first].line;
  });
  return selected;
}

}  // namespace uwscan::laser
