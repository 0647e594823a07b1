// The reconstruction under hard image conditions: turbid water, whose
// start is run again on half the image, and exposures that clip the scene
// or the features' colour, which the report names.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "uwscan/eval/trajectory_metrics.h"
#include "uwscan/fusion/self_referenced.h"
#include "uwscan/io/tum.h"
#include "uwscan/pipeline/reconstruct.h"
#include "uwscan/pipeline/testing.h"

namespace uwscan {
namespace {
namespace fs = std::filesystem;
using namespace pipeline_testing;

// A c_p 0.8 hover: tracked at 640 px its trajectory lands anywhere within
// some 20 % of the truth's scale (the tracks' error has a heavy tail
// there), and whether its start is still moving when the scan goes on is
// a lottery too. Seven builds that differ only in the last bits of the
// exact projection (seventy-first and seventy-second sessions) gave Sim(3)
// scale 0.973 / 1.068 / 0.838 / 0.810 / 0.874 / 0.858 / 0.889, ATE 8.2 /
// 7.4 / 19.3 / 10.7 / 13.0 / 5.8 / 8.7 mm, the start still moving in all
// but the sixth (settled within 2 mm, on a scale 14 % short). What held in
// all seven: tracked on half the image the hover comes nearer the truth,
// ATE 2.0-3.0 mm (scale 0.91-1.00). So this test checks that, and that a
// start still moving asks for the run on half the image and gets it; where
// the start happens to settle at 640 px, that no run again is asked, and
// half the image is tracked by hand. On the linear tracked image the hover
// was measured on (BENCHMARKS.md, "Turbid hovers: a start still moving
// runs again on half the image", "The tests on a CPU without AVX").
TEST(ReconstructTurbid, AHoverIsTrackedBetterOnHalfTheImage) {
  const fs::path root = TempFolder("turbid_half");
  sim::ScenarioOptions options = ScanOptions(640, 480, 100, 5);
  options.turbidity = "0.8";
  ReconstructJob job = SimulatedJob(root, "tank-target", options);
  const auto truth = ReadTum(job.dataset / "groundtruth.tum");
  const auto run = [&](const std::string& name, bool retry, int width) {
    job.out = root / name;
    job.retry_smaller_tracking = retry;
    job.self_referenced = fusion::SelfReferencedOptions();
    job.self_referenced.max_tracking_width = width;
    UseLinearTrackedImage(&job.self_referenced);
    // Not stopped by the machine's load (ctest runs tests side by side).
    job.self_referenced.odometry.ba.max_solver_time_s = 10.0;
    const ReconstructReport report = RunReconstruct(job);
    return std::make_pair(report,
                          ComputeTrajectoryMetrics(ReadTum(job.out / "trajectory.tum"), truth));
  };
  const auto [once, at_640] = run("once", false, 640);
  EXPECT_TRUE(once.laser_sweeps);
  EXPECT_EQ(once.pose_details.value("tracked_image_width", 0), 640);
  const bool moving = once.SmallerTrackingWidth().has_value();
  const auto [again, with_retry] = run("again", true, 640);
  TrajectoryMetrics at_half = with_retry;
  if (moving) {
    EXPECT_EQ(once.SmallerTrackingWidth(), 320);
    EXPECT_EQ(again.tracking_retried_from_width, 640);
    EXPECT_EQ(again.pose_details.value("tracked_image_width", 0), 320);
    EXPECT_TRUE(Warns(again, {"the odometry ran again at 320 px"}));
  } else {
    EXPECT_EQ(again.tracking_retried_from_width, 0);
    EXPECT_EQ(again.pose_details.value("tracked_image_width", 0), 640);
    EXPECT_FALSE(Warns(again, {"the odometry ran again"}));
    const auto [half, by_hand] = run("half", false, 320);
    EXPECT_EQ(half.pose_details.value("tracked_image_width", 0), 320);
    at_half = by_hand;
  }
  std::printf(
      "turbid hover: Sim(3) scale %.3f, ATE %.1f mm at 640 px (start %s); on half the image "
      "(%s): %.3f, %.1f mm\n",
      at_640.alignment.scale, 1e3 * at_640.ate_rmse_m, moving ? "still moving" : "settled",
      moving ? "run again" : "by hand", at_half.alignment.scale, 1e3 * at_half.ate_rmse_m);
  EXPECT_LT(at_half.ate_rmse_m, 0.75 * at_640.ate_rmse_m);
  fs::remove_all(root);
}

// In turbid water (c_p 1.0 /m) the red LED's texture is a little above
// the sensor's noise: tracked at 640 px the held frames' poses do not
// settle (tens of millimetres) and the trajectory's scale comes out far
// off; the run goes again on half the image, whose KLT windows average
// more of the noise (BENCHMARKS.md, "Turbid water, measured again"; this
// dataset: Sim(3) scale 0.59 at 640 px, 0.90 at 320). At c_p 0.8, where
// this test was written (0.77 at 640 px, 1.04 at 320), the start at 640 px
// is a lottery since (the test above).
TEST(ReconstructTurbid, AStartThatDoesNotSettleRunsAgainOnHalfTheImage) {
  const fs::path root = TempFolder("turbid");
  sim::ScenarioOptions options = ScanOptions(640, 480, 100, 5);
  options.turbidity = "1.0";
  ReconstructJob job = SimulatedJob(root, "tank-target", options);
  // The same BAs on a slow or loaded machine: the run whose retry fails
  // leaves the first run's trajectory, compared to the byte below.
  job.self_referenced.odometry.ba.max_solver_time_s = 10.0;
  const auto ground_truth = ReadTum(job.dataset / "groundtruth.tum");
  const auto run = [&](const std::string& name, bool retry) {
    job.out = root / name;
    job.retry_smaller_tracking = retry;
    const ReconstructReport report = RunReconstruct(job);
    const TrajectoryMetrics metrics =
        ComputeTrajectoryMetrics(ReadTum(job.out / "trajectory.tum"), ground_truth);
    return std::make_pair(report, metrics.alignment.scale);
  };
  const auto [once, once_scale] = run("once", false);
  const auto [again, again_scale] = run("again", true);
  std::printf("turbid hover: Sim(3) scale %.3f tracked at %d px, %.3f at %d px\n", once_scale,
              once.pose_details.value("tracked_image_width", 0), again_scale,
              again.pose_details.value("tracked_image_width", 0));
  // Without the second run: the start far from settled, and the warning
  // suggests the smaller image.
  EXPECT_EQ(once.tracking_retried_from_width, 0);
  EXPECT_EQ(once.SmallerTrackingWidth(), 320);
  EXPECT_TRUE(
      Warns(once, {"the whole trajectory rests on that start", "try --max-tracking-width 320"}));
  // With it: half the image, said in the report, and a scale nearer the truth.
  EXPECT_EQ(again.tracking_retried_from_width, 640);
  EXPECT_EQ(again.pose_details.value("tracked_image_width", 0), 320);
  EXPECT_GT(again.retried_start_change_mm, 20.0);
  EXPECT_GT(again.seconds_earlier_passes, 0.0);
  EXPECT_FALSE(again.SmallerTrackingWidth().has_value());
  EXPECT_TRUE(Warns(again, {"the odometry ran again at 320 px"}));
  const nlohmann::json json = nlohmann::json::parse(std::ifstream(job.out / "report.json"));
  EXPECT_EQ(json["tracking_retried_from_width"], 640);
  EXPECT_LT(std::abs(again_scale - 1.0), 0.5 * std::abs(once_scale - 1.0));
  EXPECT_LT(std::abs(again_scale - 1.0), 0.25);

  // If the second run fails outright (here its last frame is damaged once
  // the first run has committed its outputs), the first run's outputs
  // stand and the report says why.
  job.out = root / "failed";
  job.retry_smaller_tracking = true;
  const fs::path last_frame = job.dataset / "frames" / "000099.png";
  bool damaged = false;
  const ReconstructReport failed = RunReconstructActingOnceCommitted(
      job, [&] { fs::resize_file(last_frame, fs::file_size(last_frame) / 2); }, &damaged);
  ASSERT_TRUE(damaged);
  EXPECT_NE(failed.tracking_retry_failed.find("000099.png"), std::string::npos)
      << failed.tracking_retry_failed;
  EXPECT_EQ(failed.tracking_retried_from_width, 0);
  EXPECT_EQ(failed.pose_details.value("tracked_image_width", 0), 640);
  EXPECT_EQ(FileBytes(job.out / "trajectory.tum"), FileBytes(root / "once" / "trajectory.tum"));
  const nlohmann::json failed_json = nlohmann::json::parse(std::ifstream(job.out / "report.json"));
  EXPECT_EQ(failed_json["tracking_retry_failed"], failed.tracking_retry_failed);
  EXPECT_TRUE(Warns(failed, {"these outputs are the first run's"}));
  for (const auto& entry : fs::directory_iterator(job.out))
    EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos) << entry.path();
  fs::remove_all(root);
}

// A mono camera at the colour camera's exposure and gain gathers the light
// of all three colours: the floor's bright patches and the target's white
// squares clip, the line cannot stand out on them, and the report says so.
TEST(ReconstructClipping, AMonoCameraAtAColourCamerasExposureSaysTheSceneClips) {
  const fs::path root = TempFolder("reconstruct_clipping");
  sim::ScenarioOptions options = ScanOptions(320, 240, 12, 23);
  options.output = sim::OutputFormat::kMono;
  ReconstructJob job = SimulatedJobOnTruePoses(root, "tank-target", options);
  job.out = root / "out";
  const ReconstructReport report = RunReconstruct(job);
  EXPECT_EQ(report.frames_clipping_examined, 12);
  EXPECT_GE(report.frames_with_clipped_scene, 6);
  // A mono camera's features are in the laser's colour: measured once, above.
  EXPECT_EQ(report.frames_features_clipping_examined, 0);
  EXPECT_EQ(report.features_colour, "");
  EXPECT_GT(report.clipped_samples, report.clipping_samples_examined / 100);
  EXPECT_TRUE(Warns(
      report, {"at full scale in the laser's colour", "lower the camera's exposure or gain"}));
  const nlohmann::json json = nlohmann::json::parse(std::ifstream(job.out / "report.json"));
  EXPECT_EQ(json["frames_with_clipped_scene"], report.frames_with_clipped_scene);
  EXPECT_GT(json["clipped_scene_share"].get<double>(), 0.01);
  fs::remove_all(root);
}

// The simulator's pixels grow with a smaller image on the same sensor, so
// at a quarter of the thesis camera's width and its gain each pixel gathers
// 16 times the light: the red LED's colour, which the odometry tracks,
// clips on much of the image and the report says so. At a quarter of the
// gain it does not.
TEST(ReconstructClipping, AnExposureThatClipsTheFeaturesColourIsReported) {
  const fs::path root = TempFolder("reconstruct_clipped_features");
  const auto run = [&](double gain) {
    sim::ScenarioOptions options = ScanOptions(320, 240, 12, 23);
    options.gain = gain;
    ReconstructJob job =
        SimulatedJobOnTruePoses(root / std::to_string(int(gain)), "tank-target", options);
    job.out = root / ("out" + std::to_string(int(gain)));
    return RunReconstruct(job);
  };
  const ReconstructReport bright = run(4.0);
  EXPECT_EQ(bright.features_colour, "red");
  EXPECT_EQ(bright.frames_features_clipping_examined, 12);
  EXPECT_EQ(bright.frames_with_clipped_features, 12);
  EXPECT_GT(bright.ClippedFeaturesShare(), 0.2);
  EXPECT_TRUE(Warns(bright, {"the features' colour (red, lit by the floods) is at full scale",
                             "lower the camera's exposure or gain"}));
  const nlohmann::json json = nlohmann::json::parse(std::ifstream(root / "out4" / "report.json"));
  EXPECT_EQ(json["frames_with_clipped_features"], 12);
  EXPECT_EQ(json["features_colour"], "red");

  const ReconstructReport dim = run(1.0);
  EXPECT_EQ(dim.frames_features_clipping_examined, 12);
  EXPECT_EQ(dim.frames_with_clipped_features, 0);
  EXPECT_LT(dim.ClippedFeaturesShare(), 0.05);
  for (const std::string& w : dim.Warnings())
    EXPECT_EQ(w.find("features' colour"), std::string::npos) << w;
  fs::remove_all(root);
}

}  // namespace
}  // namespace uwscan
