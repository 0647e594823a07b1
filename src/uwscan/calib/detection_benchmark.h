// Detection rate and corner error of the checkerboard detectors on rendered
// boards with known corners under blur, noise and turbidity (issue 5; the
// table in docs/BENCHMARKS.md). Not a test: figures, no assertions.
#pragma once

#include <string>
#include <vector>

#include "uwscan/calib/board_render.h"
#include "uwscan/calib/checkerboard.h"

namespace uwscan {

struct DetectionCondition {
  std::string name;
  BoardRenderOptions render;
  double min_tilt_rad = 0.0;  // board tilt against the camera, uniform in [min, max]
  double max_tilt_rad = 0.6;
};

// Clear, steep (40-50 deg tilt), blur 1/2/3 px, noise 5/10/20, turbid
// (contrast 0.3, 0.15, 0.08 with blur 1.5 px and noise 3).
std::vector<DetectionCondition> StandardDetectionConditions();

struct DetectionBenchmarkRow {
  std::string condition;
  std::string detector;
  int trials = 0;
  int detected = 0;           // board found with all corners (quality gates off)
  double rms_error_px = 0.0;  // corner error vs truth over detected boards
  double max_error_px = 0.0;
};

// `trials` random board poses per condition (fixed seed), both detectors.
std::vector<DetectionBenchmarkRow> RunDetectionBenchmark(
    const BoardSpec& board, const std::vector<DetectionCondition>& conditions, int trials,
    unsigned seed);

std::string DetectionBenchmarkMarkdown(const std::vector<DetectionBenchmarkRow>& rows);

}  // namespace uwscan
