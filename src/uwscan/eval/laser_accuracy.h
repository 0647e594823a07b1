// Accuracy of laser line detections against the true line (laser_gt.csv):
// sub-pixel RMS, completeness and outlier rate (issue "laser detection").
#pragma once

#include <Eigen/Core>
#include <vector>

namespace uwscan {

struct LaserAccuracy {
  long true_lines = 0;  // scan lines the true line crosses
  long found = 0;       // of those, with a detection within 1 px
  long detections = 0;
  long outliers = 0;         // detections farther than 2 px from the true line
  double sum_squared = 0.0;  // over detections within 1 px

  double Rms() const { return found ? std::sqrt(sum_squared / found) : 0.0; }
  double Completeness() const { return true_lines ? double(found) / true_lines : 1.0; }
  double OutlierRate() const { return detections ? double(outliers) / detections : 0.0; }
  void Add(const LaserAccuracy& other);
};

// One frame. `truth` samples the true line densely (u, v); `detected` holds
// at most one point per scan line (rows if scan_rows, else columns). The true
// position on a scan line is interpolated between truth samples no more than
// `max_gap_px` apart along the scan direction.
LaserAccuracy EvaluateLaserFrame(const std::vector<Eigen::Vector2d>& truth,
                                 const std::vector<Eigen::Vector2d>& detected, bool scan_rows,
                                 double max_gap_px = 3.0);

}  // namespace uwscan
