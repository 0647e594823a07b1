#include "uwscan/pipeline/vo_run.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>

#include "uwscan/pipeline/vo_synthetic.h"

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
  fs::remove_all(root);
}

}  // namespace
}  // namespace uwscan
