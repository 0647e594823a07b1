// Motion-based scoring of line detections for a laser on a servo (thesis
// §5.5, "active features"): when the sheet turns, the line it draws on the
// scene moves across the image by about focal x angle; a bright stripe
// painted on the scene (or a reflection) stays where it is, moving only with
// the platform's slow hover. Detections that stay put on their scan line
// while the sheet has turned far enough to move the line are not the laser
// and are removed. If that would remove nearly all of a frame's
// detections, they are kept (the thesis restores demoted detections when too
// many would go): the sweep may have stalled or the scene be degenerate.
// Without a servo (no angles, or the angle does not change) nothing is
// removed: line and stripe cannot be told apart this way.
#pragma once

#include <deque>
#include <vector>

#include "uwscan/laser/detector.h"

namespace uwscan::laser {

struct SweepFilterOptions {
  double focal_px = 500.0;               // camera focal length across the line
  bool scan_rows = true;                 // as DetectorOptions::scan_rows
  double min_expected_shift_px = 8.0;    // compare with a frame the sheet has turned this far from
  int max_lag_frames = 40;               // ... at most this many frames ago (slow platform motion)
  double static_tolerance_px = 2.0;      // "stayed put": within this, or a quarter of the shift
  double restore_fraction = 0.8;         // keep all if more than this share would be removed
  int line_search = 3;                   // reference scan lines looked at on each side
  void Check() const;
};

class SweepFilter {
 public:
  explicit SweepFilter(const SweepFilterOptions& options);
  // The detections of frame `frame` with the sheet at `servo_angle_rad`,
  // without those that stayed put; `removed` gets their count.
  std::vector<LaserPoint> Filter(int frame, double servo_angle_rad,
                                 const std::vector<LaserPoint>& points, int* removed);

 private:
  struct Past {
    int frame;
    double angle_rad;
    // Across-line position per scan line (NaN: none), offset by first_line.
    int first_line = 0;
    std::vector<float> position_by_line;
    float At(int line) const;
  };
  SweepFilterOptions options_;
  std::deque<Past> history_;
};

}  // namespace uwscan::laser
