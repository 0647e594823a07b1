#include "uwscan/laser/segments.h"

#include <algorithm>
#include <cmath>
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
                                                double min_relative_strength) {
  std::vector<int> order(segments.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return segments[a].score > segments[b].score; });
  const auto mean_strength = [&](const Segment& segment) {
    double sum = 0.0;
    for (int p : segment.peaks) sum += peaks[p].strength;
    return sum / segment.peaks.size();
  };
  std::vector<bool> line_taken(line_count, false);
  std::vector<std::pair<int, int>> selected;
  double reference = -1.0;  // mean strength of the best selected segment
  for (int s : order) {
    const auto& segment = segments[s];
    if (static_cast<int>(segment.peaks.size()) < min_lines) continue;
    if (reference > 0.0 && mean_strength(segment) < min_relative_strength * reference) continue;
    int free_lines = 0;
    for (int p : segment.peaks) free_lines += !line_taken[peaks[p].line];
    if (free_lines < min_lines) continue;
    if (reference < 0.0) reference = mean_strength(segment);
    for (int p : segment.peaks) {
      if (line_taken[peaks[p].line]) continue;
      line_taken[peaks[p].line] = true;
      selected.emplace_back(p, s);
    }
  }
  std::sort(selected.begin(), selected.end(), [&](const auto& a, const auto& b) {
    return peaks[a.first].line < peaks[b.first].line;
  });
  return selected;
}

}  // namespace uwscan::laser
