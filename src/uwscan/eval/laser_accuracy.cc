#include "uwscan/eval/laser_accuracy.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace uwscan {

void LaserAccuracy::Add(const LaserAccuracy& other) {
  true_lines += other.true_lines;
  found += other.found;
  detections += other.detections;
  outliers += other.outliers;
  sum_squared += other.sum_squared;
}

LaserAccuracy EvaluateLaserFrame(const std::vector<Eigen::Vector2d>& truth,
                                 const std::vector<Eigen::Vector2d>& detected, bool scan_rows,
                                 double max_gap_px) {
  // (line coordinate, position along the line) pairs, sorted by line.
  const auto split = [&](const Eigen::Vector2d& p) {
    return scan_rows ? std::pair{p.y(), p.x()} : std::pair{p.x(), p.y()};
  };
  std::vector<std::pair<double, double>> samples;
  for (const auto& p : truth) samples.push_back(split(p));
  std::sort(samples.begin(), samples.end());
  // True position on each integer scan line the line crosses.
  std::map<long, double> true_position;
  for (size_t i = 0; i + 1 < samples.size(); ++i) {
    const auto& [l0, p0] = samples[i];
    const auto& [l1, p1] = samples[i + 1];
    if (l1 - l0 > max_gap_px) continue;
    for (long line = static_cast<long>(std::ceil(l0)); line <= std::floor(l1); ++line) {
      const double t = l1 > l0 ? (line - l0) / (l1 - l0) : 0.0;
      true_position.emplace(line, p0 + t * (p1 - p0));
    }
  }
  LaserAccuracy accuracy;
  accuracy.true_lines = static_cast<long>(true_position.size());
  accuracy.detections = static_cast<long>(detected.size());
  for (const auto& d : detected) {
    const auto [line, position] = split(d);
    const auto it = true_position.find(std::lround(line));
    const double error = it == true_position.end() ? 1e9 : std::abs(position - it->second);
    if (error > 2.0) ++accuracy.outliers;
    if (error <= 1.0) {
      ++accuracy.found;
      accuracy.sum_squared += error * error;
    }
  }
  return accuracy;
}

}  // namespace uwscan
