// Motion-based scoring of line candidates for a laser on a servo (thesis
// §5.5, "active features"): when the sheet turns, the line it draws on the
// scene moves across the image by about focal x angle; a bright stripe
// painted on the scene (or a reflection) stays where it is, moving only with
// the platform's slow hover. Candidate peaks that stand where a candidate
// stood in an earlier frame the sheet has turned far enough from are not the
// laser: they are excluded before the detector picks one peak per scan line,
// so that where a stripe outshone the line, the line itself is found. The
// memory is of all candidates, not only of the selected ones: a stripe is a
// candidate in every frame but wins a scan line only where the laser is weak.
//
// If nearly all of a frame's line would go, the detector keeps it (the
// thesis restores demoted detections when too many would go): the sweep may
// have stalled or the scene be degenerate. Without a servo (no angles, or
// the angle does not change) nothing is excluded: line and stripe cannot be
// told apart this way.
#pragma once

#include <deque>
#include <vector>

#include "uwscan/laser/detector.h"

namespace uwscan::laser {

struct SweepFilterOptions {
  double focal_px = 500.0;             // camera focal length across the line
  bool scan_rows = true;               // as DetectorOptions::scan_rows
  double min_expected_shift_px = 8.0;  // compare with a frame the sheet has turned this far from
  // ... at most this long ago: 40 frames of the thesis camera's 144 Hz,
  // over which a hover moves the scene by little. A time, not a count of
  // frames: 40 frames of a 28.8 Hz camera span 1.4 s, over which the hover
  // moved the line as far as the sheet, and whole lines were taken for
  // stripes (BENCHMARKS.md, "Cameras slower than 144 Hz").
  double max_lag_s = 40.0 / 144.0;
  // Whether a frame `dt_s` earlier is within max_lag_s (a microsecond's
  // slack: frames exactly that far apart are).
  bool WithinLag(double dt_s) const { return dt_s <= max_lag_s + 1e-6; }
  // "Stood there": within this, or this share of the sheet's shift since
  // (the scene drifts across the image with the hover meanwhile; half the
  // shift is the midpoint between "stayed with the scene" and "moved with
  // the sheet").
  double static_tolerance_px = 2.0;
  double tolerance_of_shift = 0.5;
  int line_search = 1;  // reference scan lines looked at on each side
  void Check() const;
};

class SweepFilter {
 public:
  explicit SweepFilter(const SweepFilterOptions& options);
  // Starts the frame taken at `timestamp_s` with the sheet at
  // `servo_angle_rad`: picks the earlier frames the sheet has turned far
  // enough from.
  void Begin(double timestamp_s, double servo_angle_rad);
  // Whether a candidate at `position` (across the line, full-resolution px)
  // on scan line `line` stood there in one of those frames.
  // `strict`: within static_tolerance_px only, whatever the shift.
  bool IsStatic(double position, int line, bool strict = false) const;
  // Remembers the frame's candidates (all peaks, before selection).
  void End(const std::vector<LaserPoint>& candidates);
  // DetectorOptions::exclude_candidate for the current frame (valid until
  // the filter is destroyed; empty before the sheet has turned far enough).
  std::function<bool(double, int)> Predicate(bool strict = false) const;

 private:
  struct Past {
    double timestamp_s = 0.0;
    double angle_rad = 0.0;
    // Candidate positions per scan line: positions[line_start[l - first_line] ..
    // line_start[l - first_line + 1]).
    int first_line = 0;
    std::vector<int> line_start;
    std::vector<float> positions;
  };
  SweepFilterOptions options_;
  std::deque<Past> history_;
  double timestamp_s_ = 0.0;
  double angle_rad_ = 0.0;
  std::vector<std::pair<const Past*, double>> references_;  // frame, tolerance
};

}  // namespace uwscan::laser
