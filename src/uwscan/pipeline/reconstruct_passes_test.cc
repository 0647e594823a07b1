// Passes of the self-referenced odometry until the trajectory settles: a
// hull whose first pass came out far off needs more than three.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "uwscan/eval/trajectory_metrics.h"
#include "uwscan/io/tum.h"
#include "uwscan/pipeline/evaluate_reconstruction.h"
#include "uwscan/pipeline/reconstruct.h"
#include "uwscan/pipeline/testing.h"

namespace uwscan {
namespace {
namespace fs = std::filesystem;
using namespace pipeline_testing;

// Coastal hull seed 197 at 640x480 and the full-resolution exposure
// (gain 1; BENCHMARKS.md, "Over-exposed hulls"): the first pass gives the
// shaft's features the hull's depth for half the scan and comes out 30 %
// short; the second pass, on its surface, 15 % long; the third still 5 %
// long, its shaft no better than the INS's. Each pass places the surface
// in front with the poses of the one before, so auto goes on until a pass
// moves the trajectory by less than 2 mm and 0.05 deg rms: the fourth
// moves it by centimetres, the fifth by half a millimetre, and the shaft
// beats the INS by 6x. The report gives each pass's move.
TEST(ReconstructPasses, MorePassesUntilTheTrajectorySettles) {
  const fs::path root = TempFolder("passes_settle");
  sim::ScenarioOptions options = ScanOptions(640, 480, 200, 197);
  options.turbidity = "coastal";
  options.gain = 1.0;
  ReconstructJob job = SimulatedJob(root, "hull", options);
  // The odometry's options and the linear tracked image the test was
  // written with: the tracks' robust loss at their noise
  // (fusion::SelfReferencedOdometryOptions) mends the poor start below by
  // itself (three passes 0.31 mm, scale 0.983, with its BAs at 10
  // iterations throughout), and so does the image in logarithm
  // (SelfReferencedOptions::log_offset_fraction: three passes 0.47 mm,
  // scale 0.997).
  UseOdometryBeforeTheRobustLoss(&job.self_referenced);
  UseLinearTrackedImage(&job.self_referenced);
  // Not stopped by the machine's load (ctest runs tests side by side).
  job.self_referenced.odometry.ba.max_solver_time_s = 10.0;
  // The first pass's start taken at its first attempt, although its
  // refinements diverge: the poor start the passes must recover from. (By
  // default that start is refused once, and three passes already make it:
  // checked at the end.)
  job.unsettled_start_refusals = 0;
  // Nor are the points extrapolated from its tilted plane placed again once
  // the plane settles (SurfaceModelOptions::settled_plane_width_m), which
  // alone mends much of it (three passes 0.57 mm, scale 1.017).
  job.self_referenced.surface.settled_plane_width_m = 0.0;
  const auto truth = ReadTum(job.dataset / "groundtruth.tum");
  struct Run {
    ReconstructReport report;
    double shaft_m = 1e9, scale = 0.0;
  };
  const auto run = [&](const std::string& name, int passes) {
    job.out = root / name;
    job.passes = passes;
    Run result{RunReconstruct(job)};
    const auto evaluation = EvaluateReconstruction(job.dataset, job.out);
    const SurfaceAccuracy* shaft = evaluation.compensated.Surface("shaft");
    EXPECT_NE(shaft, nullptr) << name;
    if (shaft) result.shaft_m = shaft->robust_fit_rms_m;
    if (!job.poses_file) {
      result.scale =
          ComputeTrajectoryMetrics(ReadTum(job.out / "trajectory.tum"), truth).alignment.scale;
    }
    return result;
  };
  const Run automatic = run("auto", 0);
  const Run three = run("three", 3);
  job.poses_file = job.dataset / "ins.tum";
  const Run ins = run("ins", 1);
  std::printf(
      "shaft cylinder residual: auto (%d passes) %.3f mm, scale %.4f; three passes %.3f mm, "
      "scale %.4f; INS %.3f mm\n",
      automatic.report.passes, 1e3 * automatic.shaft_m, automatic.scale, 1e3 * three.shaft_m,
      three.scale, 1e3 * ins.shaft_m);
  const ReconstructReport& report = automatic.report;
  EXPECT_GT(report.passes, 3);
  ASSERT_EQ(report.pass_changes.size(), static_cast<size_t>(report.passes - 1));
  for (int pass = ReconstructJob::kMinAutoPasses; pass < report.passes; ++pass) {
    const fusion::PoseChange& change = report.pass_changes[pass - 2];
    EXPECT_TRUE(change.moved_m >= job.passes_settled_m ||
                change.turned_deg >= job.passes_settled_deg)
        << "pass " << pass << " had settled, yet another followed";
  }
  EXPECT_EQ(report.passes_settled, true);
  EXPECT_LT(report.pass_changes.back().moved_m, job.passes_settled_m);
  for (const std::string& warning : report.Warnings())
    EXPECT_EQ(warning.find("not settled"), std::string::npos) << warning;
  EXPECT_FALSE(three.report.passes_settled.has_value());  // a forced count
  EXPECT_EQ(three.report.pass_changes.size(), 2u);
  // Three passes: 1.99 mm against the INS's 1.95, scale 1.055; auto:
  // 0.29 mm, 0.991 when written. Builds that differ only in the last bits
  // of the exact projection (BENCHMARKS.md, "The exact projection in fewer
  // Newton steps"): auto 0.30 mm, 0.989 in all three; three passes 0.29 /
  // 2.14 / 1.98 mm, 0.988 / 1.064 / 1.058. Three passes may already make
  // it; auto, going on until the trajectory settles, always does.
  EXPECT_LT(automatic.shaft_m, 0.5 * ins.shaft_m);
  EXPECT_LT(automatic.shaft_m, 0.5e-3);
  EXPECT_LT(std::abs(automatic.scale - 1.0), 0.015);
  EXPECT_LT(automatic.shaft_m, 1.1 * three.shaft_m);
  EXPECT_LT(std::abs(automatic.scale - 1.0), std::abs(three.scale - 1.0) + 0.002);

  // Passes that cannot settle (a tolerance no trajectory meets) stop once
  // they no longer converge (here: each move below a twentieth of the one
  // before; the fourth moves it by a tenth of the third's), and the report
  // says so.
  job.poses_file.reset();
  job.passes_settled_m = 1e-9;
  job.passes_settled_deg = 1e-9;
  job.passes_converging_ratio = 0.05;
  const ReconstructReport unsettled = run("unsettled", 0).report;
  EXPECT_EQ(unsettled.passes, 4);
  EXPECT_EQ(unsettled.passes_settled, false);
  const auto& changes = unsettled.pass_changes;
  ASSERT_EQ(changes.size(), 3u);
  EXPECT_GE(changes[2].moved_m, job.passes_converging_ratio * changes[1].moved_m);
  bool said = false;
  for (const std::string& warning : unsettled.Warnings())
    said |= warning.find("the trajectory had not settled after 4 passes") != std::string::npos;
  EXPECT_TRUE(said);

  // By default the diverging start is refused once, and the next attempt
  // is a better one: three passes beat the INS too (0.29 mm, scale 0.988
  // when written; 0.29 mm, 0.986 with the robust loss at the tracks' noise).
  ReconstructJob defaults;
  defaults.dataset = job.dataset;
  defaults.quiet = true;
  defaults.self_referenced.odometry.ba.max_solver_time_s = 10.0;
  job = defaults;
  const Run refused = run("three_refused", 3);
  std::printf("three passes, the diverging start refused: %.3f mm, scale %.4f\n",
              1e3 * refused.shaft_m, refused.scale);
  // (0.305 / 0.305 / 0.305 mm, 0.992 / 0.990 / 0.992 in the three builds.)
  EXPECT_LT(refused.shaft_m, 0.5 * ins.shaft_m);
  EXPECT_LT(std::abs(refused.scale - 1.0), 0.015);
  fs::remove_all(root);
}

}  // namespace
}  // namespace uwscan
