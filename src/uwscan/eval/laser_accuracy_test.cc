#include "uwscan/eval/laser_accuracy.h"

#include <gtest/gtest.h>

namespace uwscan {
namespace {

TEST(LaserAccuracy, CountsByHand) {
  // True line u = 10 + 0.5 v, sampled every 0.5 px in v over rows 0..10.
  std::vector<Eigen::Vector2d> truth;
  for (double v = 0.0; v <= 10.0; v += 0.5) truth.emplace_back(10.0 + 0.5 * v, v);
  std::vector<Eigen::Vector2d> detected = {
      {10.1, 0},   // error 0.1
      {11.3, 2},   // true 11.0: error 0.3
      {14.0, 4},   // true 12.0: error 2.0, neither found (> 1) nor an outlier (not > 2)
      {20.0, 6},   // outlier
      {50.0, 30},  // no true line on row 30: outlier
  };
  const LaserAccuracy a = EvaluateLaserFrame(truth, detected, true);
  EXPECT_EQ(a.true_lines, 11);
  EXPECT_EQ(a.detections, 5);
  EXPECT_EQ(a.found, 2);
  EXPECT_EQ(a.outliers, 2);
  EXPECT_NEAR(a.Rms(), std::sqrt((0.01 + 0.09) / 2.0), 1e-12);
  EXPECT_NEAR(a.Completeness(), 2.0 / 11.0, 1e-12);
  EXPECT_NEAR(a.OutlierRate(), 0.4, 1e-12);
}

TEST(LaserAccuracy, ColumnsAndGapsInTruth) {
  // A horizontal line with a hole between u = 5 and u = 20 (occlusion).
  std::vector<Eigen::Vector2d> truth;
  for (double u = 0; u <= 5; u += 1) truth.emplace_back(u, 100.25);
  for (double u = 20; u <= 25; u += 1) truth.emplace_back(u, 100.25);
  const LaserAccuracy a = EvaluateLaserFrame(truth, {{3, 100.0}, {12, 100.0}}, false);
  EXPECT_EQ(a.true_lines, 12);
  EXPECT_EQ(a.found, 1);
  EXPECT_EQ(a.outliers, 1);  // column 12 lies in the hole
}

}  // namespace
}  // namespace uwscan
