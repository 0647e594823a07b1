// Grouping of line peaks into connected segments and selection of the
// strongest non-overlapping ones (thesis §5.3, score eq. 5.1).
#pragma once

#include <vector>

namespace uwscan::laser {

struct Peak {
  int line = 0;         // scan line index (row when scanning rows)
  double position = 0;  // full-resolution sub-pixel position along the line
  float strength = 0;   // b(n): band-pass response in log-intensity units
  int channel = 0;
  // Where the peak came from, so that the sub-pixel fit can run after
  // selection: sample index on its channel's scan line.
  int sample = 0;
  int offset = 0;
  int stride = 1;
};

struct Segment {
  std::vector<int> peaks;  // indices into the peak list, increasing line
  double score = 0.0;      // s = m + 1e4 * sum b(n)   (eq. 5.1)
};

// Peaks must be sorted by line. Consecutive peaks join a segment when their
// lines differ by at most max_gap + 1 and positions by at most max_jump
// (scaled with the line gap).
std::vector<Segment> GroupPeaks(const std::vector<Peak>& peaks, int max_jump, int max_gap);

// Takes segments by decreasing score; a segment contributes its peaks on
// lines not yet taken, if at least min_lines of them remain and its mean
// strength is at least `min_relative_strength` of the mean strength of the
// best segment (a faint texture stripe is not the laser). With
// `continuity_px` > 0, after the best segment those that continue the line
// taken so far (an end within continuity_px, plus a pixel per scan line
// between, of it) go first, by score, and the others after them. Returns
// the selected peak indices with their segment ids (index into `segments`).
std::vector<std::pair<int, int>> SelectSegments(const std::vector<Peak>& peaks,
                                                const std::vector<Segment>& segments,
                                                int line_count, int min_lines,
                                                double min_relative_strength = 0.0,
                                                double continuity_px = 0.0);

}  // namespace uwscan::laser
