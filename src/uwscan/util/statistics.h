// Small order statistics shared by the calibration, the odometry and the
// evaluation.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

namespace uwscan {

// The upper median (element n/2 after sorting); 0 for no values.
inline double Median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

// Root mean square; 0 for no values.
inline double Rms(const std::vector<double>& values) {
  double sum = 0.0;
  for (double v : values) sum += v * v;
  return values.empty() ? 0.0 : std::sqrt(sum / values.size());
}

}  // namespace uwscan
