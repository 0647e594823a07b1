#include "uwscan/laser/sweep_filter.h"

#include <gtest/gtest.h>

namespace uwscan::laser {
namespace {

std::vector<LaserPoint> Column(double u, int first_row, int rows) {
  std::vector<LaserPoint> points;
  for (int v = first_row; v < first_row + rows; ++v) points.push_back({u, double(v)});
  return points;
}

// Candidates of a line that moves with the servo (1 px per frame at focal
// 500 px and 2 mrad per frame) and of a stripe that stays at u = 100: from
// the frame the sheet has turned 8 px on, the stripe's candidates are
// static, the line's are not (nor is anything between them).
TEST(SweepFilter, FlagsCandidatesThatStayPutWhileTheSheetSweeps) {
  SweepFilterOptions options;
  options.focal_px = 500.0;
  SweepFilter filter(options);
  for (int frame = 0; frame < 30; ++frame) {
    filter.Begin(frame / 144.0, 0.002 * frame);
    const double laser_u = 300.0 + frame;
    if (frame >= 8) {  // 500 px x 0.016 rad = 8 px since frame 0
      ASSERT_TRUE(filter.Predicate());
      EXPECT_TRUE(filter.IsStatic(100.3, 50)) << frame;
      EXPECT_TRUE(filter.Predicate()(99.1, 120)) << frame;
      EXPECT_FALSE(filter.IsStatic(laser_u, 50)) << frame;
      EXPECT_FALSE(filter.IsStatic(200.0, 50)) << frame;
      EXPECT_FALSE(filter.IsStatic(100.3, 500)) << frame;  // no candidates on that line
      // Strict: only within static_tolerance_px (2 px), whatever the shift.
      EXPECT_TRUE(filter.IsStatic(102.0, 50, /*strict=*/true)) << frame;
      EXPECT_FALSE(filter.IsStatic(103.5, 50, /*strict=*/true)) << frame;
    } else {
      EXPECT_FALSE(filter.Predicate()) << frame;  // the sheet has not turned far enough
      EXPECT_FALSE(filter.IsStatic(100.3, 50));
    }
    std::vector<LaserPoint> candidates = Column(laser_u, 0, 200);
    const auto stripe = Column(100.2, 0, 200);
    candidates.insert(candidates.end(), stripe.begin(), stripe.end());
    filter.End(candidates);
  }
}

// A candidate is compared with frames up to 0.28 s back (40 frames at
// 144 Hz), whatever the camera's rate: at 28.8 Hz, a candidate standing
// where one stood 8 frames (0.28 s) back is static, but not where one
// stood 9 frames (0.31 s) back. Counted in frames, the hover's motion over
// 40 frames of 28.8 Hz (1.4 s) had carried the line onto where others had
// stood, and lines were taken for stripes.
TEST(SweepFilter, LooksBackTheSameTimeAtAnyFrameRate) {
  SweepFilterOptions options;
  options.focal_px = 500.0;
  for (const int lag : {8, 9}) {
    SweepFilter filter(options);
    for (int frame = 0; frame <= lag; ++frame) {
      filter.Begin(frame / 28.8, 0.01 * frame);  // 5 px per frame
      if (frame == lag) {
        ASSERT_TRUE(filter.Predicate());
        // Where frame 0 had its only candidate off the line:
        EXPECT_EQ(filter.IsStatic(100.0, 50), lag == 8) << lag;
      }
      filter.End(frame == 0 ? Column(100.0, 0, 100) : Column(300.0 + 5 * frame, 0, 100));
    }
  }
}

// Without a sweep (constant angle) nothing can be told apart: no verdicts.
TEST(SweepFilter, NothingIsStaticWithoutASweep) {
  SweepFilterOptions options;
  options.focal_px = 500.0;
  SweepFilter still(options);
  for (int frame = 0; frame < 20; ++frame) {
    still.Begin(frame / 144.0, 0.1);
    EXPECT_FALSE(still.Predicate());
    EXPECT_FALSE(still.IsStatic(300.0, 10));
    still.End(Column(300.0, 0, 100));
  }
  SweepFilterOptions bad = options;
  bad.focal_px = 0.0;
  EXPECT_ANY_THROW(SweepFilter{bad});
}

}  // namespace
}  // namespace uwscan::laser
