#include "uwscan/pipeline/vo_run.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>

#include "uwscan/pipeline/testing.h"
#include "uwscan/pipeline/vo_synthetic.h"
#include "uwscan/util/error.h"

namespace uwscan {
namespace {

namespace fs = std::filesystem;

// `uwscan vo` on a 10 m synthetic transect in medium water (320x240): the
// keyframes held before the window (BundleAdjustmentOptions::
// history_keyframes, on by default) keep each point's earlier rays in the
// windowed BA. Without them the scale wandered from window to window
// (BENCHMARKS.md, "Held keyframes before the window").
TEST(VoRun, HeldKeyframesBeforeTheWindowHalveTheDrift) {
  const fs::path root =
      fs::temp_directory_path() / ("uwscan_vo_run_test_" + std::to_string(::getpid()));
  SyntheticVoOptions synth;
  synth.frames = 300;
  synth.width = 320;
  synth.length_m = 10.0;
  synth.medium = "medium";
  WriteSyntheticVoDataset(root / "transect", synth);
  auto run = [&](int history) {
    VoJob job;
    job.dataset_dir = root / "transect";
    job.trajectory_out = root / ("history" + std::to_string(history) + ".tum");
    job.mask_laser = true;
    job.quiet = true;
    job.odometry.ba.history_keyframes = history;
    job.odometry.ba.max_solver_time_s = 10;  // the same BAs on a slow machine
    const VoRunSummary summary = RunVisualOdometry(job);
    EXPECT_TRUE(summary.metrics.has_value());
    return summary.metrics.value_or(TrajectoryMetrics{});
  };
  const int held = VoJob().odometry.ba.history_keyframes;
  const TrajectoryMetrics without = run(0), with = run(held);
  std::printf("history 0: ATE %.2f mm, drift %.3f %% | history %d: ATE %.2f mm, drift %.3f %%\n",
              1e3 * without.ate_rmse_m, without.drift_trans_percent, held, 1e3 * with.ate_rmse_m,
              with.drift_trans_percent);
  EXPECT_GT(held, 0) << "on by default";
  EXPECT_GE(with.associated, 295);
  EXPECT_LT(with.drift_trans_percent, 0.6 * without.drift_trans_percent);
  EXPECT_LT(with.ate_rmse_m, 0.6 * without.ate_rmse_m);
  // The transect moves from its first frame: no word of waiting to start.
  VoJob first_frames;
  first_frames.dataset_dir = root / "transect";
  first_frames.trajectory_out = root / "first_frames.tum";
  first_frames.mask_laser = true;
  first_frames.quiet = true;
  first_frames.max_frames = 60;
  const VoRunSummary first = RunVisualOdometry(first_frames);
  EXPECT_EQ(first.frames, 60);
  for (const std::string& warning : first.warnings)
    EXPECT_EQ(warning.find("waited to start"), std::string::npos) << warning;
  // --max-frames 0 is every frame, as for `reconstruct`; below 0 is a usage error.
  first_frames.max_frames = -1;
  EXPECT_THROW(first_frames.Check(), UsageError);
  fs::remove_all(root);
}

// A hovering platform gives monocular odometry no parallax to start from:
// the run says so instead of leaving an empty trajectory unexplained.
TEST(VoRun, AHoverThatNeverStartsIsExplained) {
  const fs::path root = pipeline_testing::TempFolder("vo_run_hover");
  sim::SimulateScenario("tank-target", pipeline_testing::ScanOptions(320, 240, 30, 5),
                        root / "hover");
  VoJob job;
  job.dataset_dir = root / "hover";
  job.trajectory_out = root / "hover.tum";
  job.mask_laser = true;
  job.quiet = true;
  const VoRunSummary summary = RunVisualOdometry(job);
  EXPECT_EQ(summary.posed, 0);
  ASSERT_FALSE(summary.warnings.empty());
  EXPECT_EQ(summary.warnings.front().rfind("the odometry never started: monocular odometry "
                                           "starts once the features have moved 5 % of the "
                                           "image width",
                                           0),
            0u)
      << summary.warnings.front();
  fs::remove_all(root);
}

}  // namespace
}  // namespace uwscan
