// Laser line pixels on a detected checkerboard, for projector calibration
// from images (a minimal extractor until the laser/ layer's detector is
// available): green excess G - (R + B) / 2 (or grey for mono images),
// column- or row-wise peak inside the board's outline, centre of gravity
// over +-3 px.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "uwscan/calib/board.h"

namespace uwscan {

struct LaserPointOptions {
  double min_peak = 40.0;  // grey levels above the row's median
  int half_window = 3;
};

std::vector<Eigen::Vector2d> ExtractLaserPixels(const cv::Mat& image, const BoardSpec& board,
                                                const std::vector<Eigen::Vector2d>& corners,
                                                const LaserPointOptions& options = {});

}  // namespace uwscan
