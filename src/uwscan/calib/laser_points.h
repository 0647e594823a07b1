// Laser pixels on a calibration target: the thesis line detector
// (laser/detector.h, §5.3) on the board image, restricted to the target's
// outline in the image (board plane, known from the board pose).
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "uwscan/calib/board.h"
#include "uwscan/geometry/rigid3d.h"
#include "uwscan/sensor/camera.h"

namespace uwscan {

// The planar target around the board in the image: the full board (the
// outer ring of squares beyond the inner corners) plus `margin_m` of plain
// target on every side, projected with `camera` at the board pose and
// sampled along the edges (so lens distortion and refraction bend it right).
std::vector<cv::Point2f> TargetOutline(const Camera& camera, const BoardSpec& board,
                                       const Rigid3d& camera_from_board, double margin_m);

struct LaserPointOptions {
  double min_peak = 40.0;  // grey levels (8-bit scale) above the scan line's median
  int half_window = 3;     // centre of gravity over +-half_window px around the peak
};

// The laser line's sub-pixel points inside `outline`. `image` is B G R
// (demosaic raw frames first) or mono, 8 or 16 bit. On colour images the
// signal is the laser colour's excess over the other two channels (green -
// (red + blue) / 2 for a green laser), in which the grey board vanishes and
// only the line is left; on mono images the image itself. Per scan line the
// strongest peak inside the outline, centre of gravity above the median;
// rows and columns are scanned and the direction with more points wins (the
// line may run either way). The thesis detector (laser/) is tuned for scenes
// and rejects the line next to the board's strong square edges.
std::vector<Eigen::Vector2d> DetectLaserOnTarget(const cv::Mat& image,
                                                 const std::vector<cv::Point2f>& outline,
                                                 int laser_channel = 1,
                                                 const LaserPointOptions& options = {});

}  // namespace uwscan
