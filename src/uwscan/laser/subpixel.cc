#include "uwscan/laser/subpixel.h"

#include <algorithm>
#include <cmath>

namespace uwscan::laser {

double GaussianPeakPosition(const float* samples, int count, int k, int half_width,
                            float background, float saturation) {
  if (samples[k] >= saturation) {
    // Saturated: the flat top carries no position. Use the midpoint of the
    // two flanks where they cross half the height above the background
    // (interpolated linearly); symmetric, so unbiased for a symmetric line.
    int left = k, right = k;
    while (left > 0 && samples[left - 1] >= saturation) --left;
    while (right + 1 < count && samples[right + 1] >= saturation) ++right;
    const float level = background + 0.5f * (samples[k] - background);
    double left_cross = -1.0, right_cross = -1.0;
    for (int j = left - 1; j >= 0 && j >= left - 4; --j) {
      if (samples[j] < level) {
        left_cross = j + (level - samples[j]) / (samples[j + 1] - samples[j]);
        break;
      }
    }
    for (int j = right + 1; j < count && j <= right + 4; ++j) {
      if (samples[j] < level) {
        right_cross = j - (level - samples[j]) / (samples[j - 1] - samples[j]);
        break;
      }
    }
    if (left_cross >= 0.0 && right_cross >= 0.0) return 0.5 * (left_cross + right_cross);
    return 0.5 * (left + right);
  }
  // Weighted least squares of ln(I) = c0 + c1 t + c2 t^2, t = i - k.
  double s[5] = {0, 0, 0, 0, 0};  // sums of w t^j, j = 0..4
  double r[3] = {0, 0, 0};        // sums of w t^j ln I
  int used = 0;
  for (int t = -half_width; t <= half_width; ++t) {
    const int i = k + t;
    if (i < 0 || i >= count) continue;
    const double value = samples[i] - background;
    if (!(value > 1e-6)) continue;
    const double w = value * value;
    const double l = std::log(value);
    double tj = 1.0;
    for (int j = 0; j < 5; ++j) {
      s[j] += w * tj;
      if (j < 3) r[j] += w * tj * l;
      tj *= t;
    }
    ++used;
  }
  if (used < 3) return k;
  // Solve the 3x3 normal equations by Cramer's rule.
  const double a[3][3] = {{s[0], s[1], s[2]}, {s[1], s[2], s[3]}, {s[2], s[3], s[4]}};
  const auto det3 = [](const double m[3][3]) {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  };
  const double det = det3(a);
  if (!(std::abs(det) > 1e-30)) return k;
  double m1[3][3], m2[3][3];
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      m1[i][j] = j == 1 ? r[i] : a[i][j];
      m2[i][j] = j == 2 ? r[i] : a[i][j];
    }
  }
  const double c1 = det3(m1) / det;
  const double c2 = det3(m2) / det;
  if (!(c2 < 0.0)) return k;  // not a peak
  const double offset = -c1 / (2.0 * c2);
  if (!(std::abs(offset) <= 1.0)) return k;
  return k + offset;
}

}  // namespace uwscan::laser
