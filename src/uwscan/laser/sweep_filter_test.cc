#include "uwscan/laser/sweep_filter.h"

#include <gtest/gtest.h>

namespace uwscan::laser {
namespace {

std::vector<LaserPoint> Column(double u, int first_row, int rows) {
  std::vector<LaserPoint> points;
  for (int v = first_row; v < first_row + rows; ++v) points.push_back({u, double(v)});
  return points;
}

// A line that moves with the servo (1 px per frame at focal 500 px and
// 2 mrad per frame) and a stripe that stays at u = 100 on rows 0-19: from the
// frame the sheet has turned 8 px on, the stripe's detections go, the line's
// stay.
TEST(SweepFilter, RemovesWhatStaysPutWhileTheSheetSweeps) {
  SweepFilterOptions options;
  options.focal_px = 500.0;
  SweepFilter filter(options);
  int total_removed = 0;
  for (int frame = 0; frame < 30; ++frame) {
    std::vector<LaserPoint> points = Column(300.0 + frame, 20, 200);  // the laser
    const auto stripe = Column(100.2, 0, 20);
    points.insert(points.end(), stripe.begin(), stripe.end());
    int removed = 0;
    const auto kept = filter.Filter(frame, 0.002 * frame, points, &removed);
    total_removed += removed;
    if (frame >= 8) {  // 500 px x 0.016 rad = 8 px since frame 0
      EXPECT_EQ(removed, 20) << frame;
      for (const LaserPoint& p : kept) EXPECT_GT(p.u, 299.0);
    } else {
      EXPECT_EQ(removed, 0) << frame;  // the sheet has not turned far enough yet
    }
  }
  EXPECT_EQ(total_removed, 22 * 20);
}

// Without a sweep (constant angle) nothing can be told apart: nothing goes.
// And when nearly everything stayed put, all is kept (the sweep stalled).
TEST(SweepFilter, KeepsAllWithoutASweepOrWhenNearlyAllStayed) {
  SweepFilterOptions options;
  options.focal_px = 500.0;
  SweepFilter still(options);
  for (int frame = 0; frame < 20; ++frame) {
    int removed = 0;
    EXPECT_EQ(still.Filter(frame, 0.1, Column(300.0, 0, 100), &removed).size(), 100u);
    EXPECT_EQ(removed, 0);
  }
  SweepFilter stalled(options);
  for (int frame = 0; frame < 20; ++frame) {
    int removed = 0;
    // The line does not move although the angle changes (a degenerate scene).
    EXPECT_EQ(stalled.Filter(frame, 0.002 * frame, Column(300.0, 0, 100), &removed).size(), 100u);
    EXPECT_EQ(removed, 0);
  }
}

}  // namespace
}  // namespace uwscan::laser
