#include "uwscan/pipeline/reconstruct.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "uwscan/eval/trajectory_metrics.h"
#include "uwscan/io/dataset.h"
#include "uwscan/io/ply.h"
#include "uwscan/io/tum.h"
#include "uwscan/pipeline/evaluate_reconstruction.h"
#include "uwscan/pipeline/testing.h"
#include "uwscan/sim/simulate.h"
#include "uwscan/util/error.h"
#include "uwscan/util/interrupt.h"

namespace uwscan {
namespace {
namespace fs = std::filesystem;
using namespace pipeline_testing;

class ReconstructTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    root_ = fs::temp_directory_path() / ("uwscan_reconstruct_test_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    sim::ScenarioOptions options = ScanOptions(480, 360, 24, 21);
    options.motion_amplitude = 0.02;
    sim::SimulateScenario("tank-target", options, root_ / "data");
  }
  static void TearDownTestSuite() { fs::remove_all(root_); }
  static fs::path root_;
};
fs::path ReconstructTest::root_;

// With the true trajectory the chain sim -> laser detection ->
// triangulation -> placement is exact up to detection noise, and the
// evaluation measures it through the scene.
TEST_F(ReconstructTest, TruePosesGiveMillimetreCloud) {
  ReconstructJob job;
  job.dataset = root_ / "data";
  job.out = root_ / "out_truth";
  job.poses_file = job.dataset / "groundtruth.tum";
  job.quiet = true;
  const ReconstructReport report = RunReconstruct(job);
  EXPECT_EQ(report.frames, 24);
  EXPECT_EQ(report.frames_without_pose, 0);
  EXPECT_GT(report.points, 24 * 120);
  // A colour camera at the thesis's exposure: the floor and the target's
  // white squares stay below full scale in green (0.2 % of the samples
  // clip: the line's glow where it was not found).
  EXPECT_EQ(report.frames_clipping_examined, 24);
  EXPECT_EQ(report.frames_with_clipped_scene, 0);
  EXPECT_LT(report.clipped_samples, report.clipping_samples_examined / 200);
  // The wait for the reading thread is part of the I/O time, which is part of the whole.
  EXPECT_GE(report.seconds_waiting_for_images, 0.0);
  EXPECT_LE(report.seconds_waiting_for_images, report.seconds_io);
  EXPECT_LE(report.seconds_io, report.seconds);
  for (const char* file :
       {"cloud.ply", "cloud_uncompensated.ply", "trajectory.tum", "report.json"}) {
    EXPECT_TRUE(fs::exists(job.out / file)) << file;
  }
  const auto evaluation = EvaluateReconstruction(job.dataset, job.out);
  EXPECT_GT(evaluation.compensated.matched, report.points * 95 / 100);
  // At 480x360 one pixel is ~7 mm on the floor at 2 m; the line is found to
  // ~0.1 px, which the 0.8 m baseline turns into ~1 mm of range.
  EXPECT_LT(evaluation.compensated.point_error_rms_m, 0.002);
  const SurfaceAccuracy* floor = evaluation.compensated.Surface("floor");
  ASSERT_NE(floor, nullptr);
  ASSERT_GT(floor->points, 1000);
  EXPECT_LT(floor->fit_rms_m, 0.002);
  EXPECT_LT(floor->distance_error_mean_pct, 0.3);
  // Without compensation the hovering motion shows.
  EXPECT_GT(evaluation.uncompensated.point_error_rms_m,
            2.0 * evaluation.compensated.point_error_rms_m);
  EXPECT_EQ(report.frame_gaps.missing, 0);
}

// An INS logs its body's poses on its own clock: with the camera's pose in
// the body's frame and the clocks' offset, the trajectory is the camera's
// and the cloud the one its true poses give; without the pose in the
// body's frame the trajectory is the body's, 0.37 m beside the camera.
TEST_F(ReconstructTest, AnInsTrajectoryOfAnotherBodyAndClock) {
  const auto truth = ReadTum(root_ / "data" / "groundtruth.tum");
  const Rigid3d body_from_camera(
      Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d(1, 2, 3).normalized())),
      Eigen::Vector3d(0.3, -0.1, 0.2));
  const double offset_s = 12.5;  // the INS's clock behind the camera's
  std::vector<StampedPose> ins = truth;
  for (StampedPose& pose : ins) {
    pose.timestamp_s -= offset_s;
    pose.world_from_camera = pose.world_from_camera * body_from_camera.Inverse();
  }
  WriteTum(root_ / "ins_body.tum", ins);
  ReconstructJob job;
  job.dataset = root_ / "data";
  job.poses_file = root_ / "ins_body.tum";
  job.poses_time_offset_s = offset_s;
  job.quiet = true;
  // The largest distance between the run's trajectory and the truth.
  const auto run = [&](const std::string& name) {
    job.out = root_ / name;
    const ReconstructReport report = RunReconstruct(job);
    EXPECT_EQ(report.frames_without_pose, 0);
    const auto placed = ReadTum(job.out / "trajectory.tum");
    EXPECT_EQ(placed.size(), truth.size());
    double farthest = 0.0;
    for (size_t i = 0; i < std::min(placed.size(), truth.size()); ++i) {
      EXPECT_NEAR(placed[i].timestamp_s, truth[i].timestamp_s, 1e-6);
      farthest = std::max(farthest, (placed[i].world_from_camera.translation -
                                     truth[i].world_from_camera.translation)
                                        .norm());
    }
    return farthest;
  };
  job.poses_body_from_camera = body_from_camera;
  EXPECT_LT(run("out_ins_body"), 1e-6);
  const auto evaluation = EvaluateReconstruction(job.dataset, job.out);
  EXPECT_LT(evaluation.compensated.point_error_rms_m, 0.002);
  job.poses_body_from_camera.reset();
  EXPECT_GT(run("out_ins_as_camera"), 0.3);

  // Without the offset its poses cover none of the frames (they ran to the
  // end and failed with "no frame got a pose"): refused before any frame is
  // read, with the offset that aligns the two starts, and no output.
  job.poses_time_offset_s = 0.0;
  job.out = root_ / "out_ins_other_clock";
  std::string message = "no error";
  try {
    RunReconstruct(job);
  } catch (const Error& e) {
    message = e.what();
  }
  EXPECT_NE(message.find("ins_body.tum: its poses (-12.500-"), std::string::npos) << message;
  EXPECT_NE(message.find("cover none of the frames' times"), std::string::npos) << message;
  EXPECT_NE(message.find("--poses-time-offset 12.500000 would align"), std::string::npos)
      << message;
  EXPECT_FALSE(fs::exists(job.out));
}

// Frames a recorder dropped (rows missing from frames.csv) are counted
// from the timestamps and said; the frames left are placed as before.
TEST_F(ReconstructTest, DroppedFramesAreCountedAndSaid) {
  const fs::path dataset = root_ / "dropped";
  fs::copy(root_ / "data", dataset, fs::copy_options::recursive);
  std::vector<std::string> rows;
  {
    std::ifstream in(root_ / "data" / "frames.csv");
    for (std::string line; std::getline(in, line);) rows.push_back(line);
  }
  {
    std::ofstream out(dataset / "frames.csv");
    for (size_t row = 0; row < rows.size(); ++row) {
      const int index = static_cast<int>(row) - 1;  // the header is row 0
      if (index != 8 && index != 15 && index != 16) out << rows[row] << "\n";
    }
  }
  ReconstructJob job;
  job.dataset = dataset;
  job.out = root_ / "out_dropped";
  job.poses_file = dataset / "groundtruth.tum";
  job.quiet = true;
  const ReconstructReport report = RunReconstruct(job);
  EXPECT_EQ(report.frames, 21);
  EXPECT_EQ(report.frame_gaps.gaps, 2);
  EXPECT_EQ(report.frame_gaps.missing, 3);
  EXPECT_GT(report.points, 21 * 120);
  const nlohmann::json json = nlohmann::json::parse(std::ifstream(job.out / "report.json"));
  EXPECT_EQ(json["frames_missing"], 3);
  bool said = false;
  for (const auto& warning : json["warnings"])
    said = said || warning.get<std::string>().find("3 frame(s) missing") != std::string::npos;
  EXPECT_TRUE(said) << json["warnings"].dump();
}

// A live run on a machine slower than its camera (here the scan's clock
// run ten times fast: 1440 frames a second) drops frames to keep within
// the maximum lag: they are counted apart from the frames processed and
// said, the last frame is processed, and the frames kept are placed as
// exactly as ever (the true poses here, so that only the drops differ).
TEST_F(ReconstructTest, ALiveRunThatFallsBehindDropsFramesAndSaysSo) {
  const fs::path dataset = root_ / "fast_clock";
  CopyWithClockStretched(root_ / "data", dataset, 1.0 / 10.0);
  const std::vector<StampedPose> truth = ReadTum(dataset / "groundtruth.tum");
  ReconstructJob job;
  job.dataset = dataset;
  job.out = root_ / "out_fast_clock";
  job.poses_file = dataset / "groundtruth.tum";
  job.quiet = true;
  job.live = true;
  job.passes = 1;
  job.retry_smaller_tracking = false;
  job.live_max_lag_s = 0.002;  // three of this clock's frames
  const ReconstructReport report = RunReconstruct(job);
  EXPECT_GT(report.frames_dropped_live, 0);
  EXPECT_EQ(report.frames + report.frames_dropped_live, 24);
  EXPECT_EQ(report.frames_without_pose, 0);
  EXPECT_GT(report.points, report.frames * 120);
  const auto placed = ReadTum(job.out / "trajectory.tum");
  ASSERT_EQ(placed.size(), static_cast<size_t>(report.frames));
  EXPECT_NEAR(placed.back().timestamp_s, truth.back().timestamp_s, 1e-6);  // the last kept
  const nlohmann::json json = nlohmann::json::parse(std::ifstream(job.out / "report.json"));
  EXPECT_EQ(json["frames_dropped_live"], report.frames_dropped_live);
  EXPECT_EQ(json["live_max_lag_s"], 0.002);
  bool said = false;
  for (const auto& warning : json["warnings"])
    said = said || warning.get<std::string>().find(
                       "dropped to keep the live cloud within 0.002 s") != std::string::npos;
  EXPECT_TRUE(said) << json["warnings"].dump();
  const auto evaluation = EvaluateReconstruction(job.dataset, job.out);
  EXPECT_GT(evaluation.compensated.matched, report.points * 95 / 100);
  EXPECT_LT(evaluation.compensated.point_error_rms_m, 0.002);

  // A maximum lag needs a live run, and a positive one.
  job.live = false;
  EXPECT_THROW(job.Check(), UsageError);
  job.live = true;
  job.live_max_lag_s = 0.0;
  EXPECT_THROW(job.Check(), UsageError);
}

// Frames missing from a scan (dropped by the recorder, or by a live run
// that fell behind, which the odometry sees alike) are not counted as
// frames by the reading thread's guess of which frame the odometry tracks
// next: tracking every second frame it is given, it gets the tracked image
// made ahead on that thread, not on its own (Details:
// tracked_images_made_late; counted by index, the gaps here had sent half
// the tracked images to the pose thread, 12 of 25).
TEST(ReconstructTrackedAhead, GapsInTheFramesDoNotMisleadThePreparationAhead) {
  const fs::path root = TempFolder("tracked_ahead");
  ReconstructJob job = SimulatedJob(root, "tank-target", ScanOptions(480, 360, 60, 27));
  // Without gaps a few are made late all the same, where the start hands
  // over to tracking every second frame (the reader had made those ahead
  // one by one, as held).
  job.out = root / "whole";
  const ReconstructReport whole = RunReconstruct(job);
  const int late_without_gaps = whole.pose_details.value("tracked_images_made_late", 99);
  EXPECT_LE(late_without_gaps, 5);
  std::vector<std::string> rows;
  {
    std::ifstream in(job.dataset / "frames.csv");
    for (std::string line; std::getline(in, line);) rows.push_back(line);
  }
  {
    std::ofstream out(job.dataset / "frames.csv");
    for (size_t row = 0; row < rows.size(); ++row) {
      if (row == 0 || row % 5 != 0) out << rows[row] << "\n";  // every fifth frame missing
    }
  }
  job.out = root / "out";
  const ReconstructReport report = RunReconstruct(job);
  EXPECT_EQ(report.frame_gaps.missing, 11);
  EXPECT_EQ(report.track_every, 2);
  const int tracked = report.pose_details.value("tracked", 0);
  EXPECT_GT(tracked, 10);
  EXPECT_LE(report.pose_details.value("tracked_images_made_late", 99), late_without_gaps + 1)
      << tracked << " tracked";
  const auto with_gaps = EvaluateReconstruction(job.dataset, job.out);
  const auto without = EvaluateReconstruction(job.dataset, root / "whole");
  // The odometry tracks across the gaps: the cloud against the simulator's
  // surfaces as good as without them (1.08 against 1.11 mm rms when
  // written; 30 mm uncompensated).
  EXPECT_LT(with_gaps.compensated.point_error_rms_m,
            1.5 * without.compensated.point_error_rms_m + 0.0005);
  EXPECT_LT(with_gaps.compensated.point_error_rms_m,
            0.1 * with_gaps.uncompensated.point_error_rms_m);
  fs::remove_all(root);
}

// Each frame's line searched only near the frame before's (the default,
// ReconstructJob::line_window_px) is found as on whole scan lines: about
// as many points, as accurate. With the servo sweep's filter not the very
// same points (it remembers the candidates of the windows only); without
// it the same cloud, byte for byte: the frames where something turned up
// off the line (here a short segment at 0.3 m that a longer one on whole
// scan lines outranks) are detected again whole.
TEST_F(ReconstructTest, LineWindowFindsTheLineAsWholeScanLinesDo) {
  ReconstructJob job;
  job.dataset = root_ / "data";
  job.poses_file = job.dataset / "groundtruth.tum";
  job.quiet = true;
  for (const bool texture_filter : {true, false}) {
    job.texture_filter = texture_filter;
    std::vector<ReconstructReport> reports;
    std::vector<double> errors;
    for (const int window : {48, 0}) {
      job.line_window_px = window;
      job.out = root_ / ("out_window" + std::to_string(window));
      reports.push_back(RunReconstruct(job));
      EXPECT_EQ(reports.back().line_window_px, window);
      errors.push_back(EvaluateReconstruction(job.dataset, job.out).compensated.point_error_rms_m);
    }
    SCOPED_TRACE(texture_filter ? "sweep filter" : "no sweep filter");
    EXPECT_GT(reports[1].points, 24 * 100);
    EXPECT_GE(reports[0].points, reports[1].points * 98 / 100);
    EXPECT_LT(errors[0], 1.1 * errors[1]);
    if (!texture_filter) {
      EXPECT_GT(reports[0].frames_line_window_redone, 0);
      EXPECT_EQ(reports[0].points, reports[1].points);
      std::vector<std::string> clouds;
      for (const int window : {48, 0})
        clouds.push_back(FileBytes(root_ / ("out_window" + std::to_string(window)) / "cloud.ply"));
      EXPECT_TRUE(clouds[0] == clouds[1]);
    }
  }
}

// The distance to the scene along the optical axis, for the evaluation's
// viewed-point motion: against the floor plane z = 0 met by each true axis
// (the target on it stands 5 mm proud); 0 without a scene.
TEST_F(ReconstructTest, MedianViewedDepthIsTheDistanceToTheFloor) {
  std::vector<double> depths;
  for (const StampedPose& pose : ReadTum(root_ / "data" / "groundtruth.tum")) {
    const Eigen::Vector3d axis = pose.world_from_camera.rotation * Eigen::Vector3d::UnitZ();
    ASSERT_LT(axis.z(), -0.9);  // looking down
    depths.push_back(pose.world_from_camera.translation.z() / -axis.z());
  }
  std::sort(depths.begin(), depths.end());
  const double expected = depths[depths.size() / 2];
  EXPECT_GT(expected, 1.5);
  EXPECT_NEAR(MedianViewedDepth(root_ / "data"), expected, 0.006);
  const fs::path bare = root_ / "no_scene";
  fs::create_directories(bare);
  fs::copy_file(root_ / "data" / "groundtruth.tum", bare / "groundtruth.tum",
                fs::copy_options::overwrite_existing);
  EXPECT_EQ(MedianViewedDepth(bare), 0.0);
}

// A dataset of every 5th frame of a 144 Hz camera (a 28.8 Hz one, or a
// scan thinned out) against its 144 Hz ground truth: each frame takes the
// pose at its own time. Five poses lie within half of the frames' interval
// of each frame; the evaluation had taken the last of them, 14 ms late,
// and put 3.5 mm of error on a cloud placed with the true poses.
TEST(PosesByFrame, EachFrameTakesThePoseNearestItsTime) {
  const fs::path root =
      fs::temp_directory_path() / ("uwscan_poses_by_frame_" + std::to_string(::getpid()));
  fs::create_directories(root);
  const double period = 1.0 / 144.0;
  std::vector<StampedPose> poses;
  for (int i = 0; i < 100; ++i) {
    poses.push_back({i * period, Rigid3d({1, 0, 0, 0}, Eigen::Vector3d(i * period, 0, 0))});
  }
  WriteTum(root / "truth.tum", poses);
  FramesCsvWriter writer(root / "frames.csv", /*with_laser_angle=*/false);
  for (int index = 0; index < 95; index += 5) {
    FrameRecord record;
    record.index = index;
    record.timestamp_s = index * period;
    record.file = FrameFileName(index);
    writer.Add(record);
  }
  // A frame four of the poses' periods past the last pose has none.
  writer.Add({95, 103 * period, FrameFileName(95), {}, {}});
  writer.Commit();
  const std::map<int, Rigid3d> by_frame = PosesByFrame(root / "truth.tum", root / "frames.csv");
  EXPECT_EQ(by_frame.size(), 19u);
  for (const auto& [index, pose] : by_frame) {
    EXPECT_NEAR(pose.translation.x(), index * period, 1e-12) << "frame " << index;
  }
  EXPECT_EQ(by_frame.count(95), 0u);
  fs::remove_all(root);
}

// A drifting external trajectory (INS-like) degrades the cloud measurably.
TEST_F(ReconstructTest, DriftingPosesDegradeTheCloud) {
  const fs::path data = root_ / "data";
  auto poses = ReadTum(data / "groundtruth.tum");
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.002);
  for (size_t i = 0; i < poses.size(); ++i) {
    poses[i].world_from_camera.translation += Eigen::Vector3d(0.002 * i, noise(rng), noise(rng));
  }
  WriteTum(root_ / "drift.tum", poses);
  ReconstructJob job;
  job.dataset = data;
  job.out = root_ / "out_drift";
  job.poses_file = root_ / "drift.tum";
  job.quiet = true;
  RunReconstruct(job);
  const auto evaluation = EvaluateReconstruction(data, job.out);
  EXPECT_GT(evaluation.compensated.point_error_rms_m, 0.005);
}

// The same dataset gives the same trajectory, bit for bit, with the heap
// in another state for each run: no decision may hang on timing or on
// addresses (the tracker once ordered revived tracks by the address of
// their anchor image, and runs of a coastal transect differed when the
// image-reading thread's allocations moved it; that case needs the
// thread's timing to show, see BENCHMARKS.md "Reproducibility").
TEST(ReconstructReproducibility, SameDatasetSameTrajectory) {
  const fs::path root = TempFolder("reproducible");
  sim::ScenarioOptions options = ScanOptions(480, 360, 40, 21);
  ReconstructJob job = SimulatedJob(root, "tank-target", options);
  std::vector<std::string> trajectories;
  std::vector<std::unique_ptr<char[]>> clutter;  // moves later allocations elsewhere
  for (int run = 0; run < 3; ++run) {
    job.out = root / ("run" + std::to_string(run));
    const ReconstructReport report = RunReconstruct(job);
    EXPECT_EQ(report.track_every, 2);             // auto at 144 Hz
    EXPECT_EQ(report.smoothing_half_window, 10);  // auto at 144 Hz
    EXPECT_EQ(report.contrast_scale, 0.0);        // auto on a servo sweep
    EXPECT_TRUE(report.async_bundle_adjustment);  // auto at 144 Hz: reproducible all the same
    trajectories.push_back(FileBytes(job.out / "trajectory.tum"));
    for (int i = 0; i < 1000; ++i) clutter.emplace_back(new char[size_t(16 + 97 * i % 4096)]);
  }
  ASSERT_GT(std::count(trajectories[0].begin(), trajectories[0].end(), '\n'), 20);
  EXPECT_EQ(trajectories[1], trajectories[0]);
  EXPECT_EQ(trajectories[2], trajectories[0]);
  // Replayed at the camera's pace (`bench pipeline --live`): the reading
  // thread now waits for each frame's time, the same trajectory all the
  // same; the run cannot end before the camera's last frame, and every
  // placed frame's lag behind the camera is measured.
  job.out = root / "live";
  job.live = true;
  job.passes = 1;
  job.retry_smaller_tracking = false;
  const ReconstructReport live = RunReconstruct(job);
  EXPECT_EQ(FileBytes(job.out / "trajectory.tum"), trajectories[0]);
  const double last_frame_s = live.sequence_duration_s * 39.0 / 40.0;
  EXPECT_GE(live.seconds, last_frame_s);
  ASSERT_TRUE(live.live_lag.has_value());
  EXPECT_GT(live.live_lag->last_s, 0.0);
  EXPECT_GE(live.live_lag->max_s, live.live_lag->median_s);
  EXPECT_GE(live.live_lag->median_s, 0.0);
  EXPECT_LE(live.live_lag->max_at_scan_s, last_frame_s);
  // A board on the floor stands on it, not in front: one pass is all a
  // tank scan needs, nothing to warn of (ReconstructPasses for a hull).
  EXPECT_FALSE(live.surface_in_front);
  for (const std::string& warning : live.Warnings())
    EXPECT_EQ(warning.find("standing in front"), std::string::npos) << warning;
  fs::remove_all(root);
}

// --contrast-scale auto: a fixed laser scans by the platform's motion,
// which carries the seabed's texture through the light's whole fall-off;
// equalising the linear tracked image's contrast then halves the trajectory
// error of a coastal 20 m transect (640x480, 200 frames: ATE 26 vs 67 mm on
// this seed; BENCHMARKS.md, "Contrast equalised in the self-referenced
// scan"). On servo sweeps auto leaves it off (the tank hover in
// ReconstructReproducibility says 0). The image in logarithm (the default,
// --log-offset) takes the light's gain out too: without the equalisation
// it gives 31 mm here (BENCHMARKS.md, "The tracked image in logarithm").
TEST(ReconstructContrast, AFixedLaserScanEqualisesTheTrackedContrast) {
  const fs::path root = TempFolder("contrast");
  sim::ScenarioOptions options = ScanOptions(640, 480, 200, 11);
  options.turbidity = "coastal";
  ReconstructJob job = SimulatedJob(root, "seabed-transect", options);
  const auto ground_truth = ReadTum(job.dataset / "groundtruth.tum");
  const auto run = [&](const std::string& name, std::optional<double> contrast_scale,
                       double log_offset) {
    job.out = root / name;
    job.contrast_scale = contrast_scale;
    job.self_referenced.log_offset_fraction = log_offset;
    const ReconstructReport report = RunReconstruct(job);
    EXPECT_EQ(report.frames_without_pose, 0) << name;
    EXPECT_EQ(report.log_offset, log_offset) << name;
    return std::make_pair(
        report, ComputeTrajectoryMetrics(ReadTum(job.out / "trajectory.tum"), ground_truth));
  };
  const auto [automatic, equalised] = run("auto", std::nullopt, 0.0);
  const auto [off, plain] = run("off", 0.0, 0.0);
  const auto [log_only, logarithm] =
      run("log", 0.0, fusion::SelfReferencedOptions().log_offset_fraction);
  std::printf(
      "coastal transect: ATE %.1f mm, drift %.2f %%, scale %.4f equalised (auto, %.2f); "
      "ATE %.1f mm, drift %.2f %%, scale %.4f off; ATE %.1f mm, drift %.2f %%, scale %.4f "
      "in logarithm, not equalised\n",
      1e3 * equalised.ate_rmse_m, equalised.drift_trans_percent, equalised.alignment.scale,
      automatic.contrast_scale, 1e3 * plain.ate_rmse_m, plain.drift_trans_percent,
      plain.alignment.scale, 1e3 * logarithm.ate_rmse_m, logarithm.drift_trans_percent,
      logarithm.alignment.scale);
  EXPECT_EQ(automatic.contrast_scale, ReconstructJob::kFixedLaserContrastScale);
  EXPECT_EQ(off.contrast_scale, 0.0);
  EXPECT_EQ(log_only.contrast_scale, 0.0);
  EXPECT_LT(equalised.ate_rmse_m, 0.7 * plain.ate_rmse_m);
  EXPECT_LT(equalised.drift_trans_percent, 0.8 * plain.drift_trans_percent);
  EXPECT_LT(std::abs(equalised.alignment.scale - 1.0), std::abs(plain.alignment.scale - 1.0));
  EXPECT_LT(logarithm.ate_rmse_m, 0.7 * plain.ate_rmse_m);
  EXPECT_LT(logarithm.drift_trans_percent, 0.8 * plain.drift_trans_percent);
  EXPECT_LT(std::abs(logarithm.alignment.scale - 1.0), std::abs(plain.alignment.scale - 1.0));
  EXPECT_EQ(ParseContrastScale("auto"), std::nullopt);
  EXPECT_EQ(ParseContrastScale("0"), 0.0);
  EXPECT_EQ(ParseContrastScale("0.05"), 0.05);
  for (const char* bad : {"-0.1", "0.8", "0.05x", "", "on"})
    EXPECT_THROW(ParseContrastScale(bad), UsageError) << bad;
  fs::remove_all(root);
}

TEST_F(ReconstructTest, BadInputIsAClearErrorWithoutOutput) {
  ReconstructJob job;
  job.dataset = root_ / "missing";
  job.out = root_ / "out_missing";
  job.poses_file = root_ / "data" / "groundtruth.tum";
  EXPECT_THROW(RunReconstruct(job), Error);
  EXPECT_FALSE(fs::exists(job.out));

  // A rig without a laser (a camera-calibration dataset), and a laser the
  // rig does not have: the rig file is named.
  const fs::path no_laser = root_ / "no_laser";
  fs::create_directories(no_laser);
  for (const char* file : {"frames.csv", "groundtruth.tum"})
    fs::copy_file(root_ / "data" / file, no_laser / file);
  {
    std::ifstream in(root_ / "data" / "rig.yaml");
    std::ofstream rig(no_laser / "rig.yaml");
    for (std::string line; std::getline(in, line) && line.rfind("lasers:", 0) != 0;)
      rig << line << "\n";
  }
  job.dataset = no_laser;
  job.out = root_ / "out_no_laser";
  const auto message = [&] {
    try {
      RunReconstruct(job);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message().find((no_laser / "rig.yaml").string() + ": the rig has no laser"),
            std::string::npos)
      << message();
  EXPECT_FALSE(fs::exists(job.out));
  job.dataset = root_ / "data";
  job.laser_name = "laser9";
  EXPECT_NE(message().find("rig.yaml: the rig has no laser named 'laser9'"), std::string::npos)
      << message();
  EXPECT_FALSE(fs::exists(job.out));
}

// An output that cannot be written at the end (here report.json's
// temporary name is taken by a folder; a disk that fills up on the last
// file does the same) leaves none of the others under their final names:
// each is written whole under its temporary name before any is renamed.
TEST_F(ReconstructTest, AnOutputThatCannotBeWrittenLeavesNoneOfTheOthers) {
  ReconstructJob job;
  job.dataset = root_ / "data";
  job.poses_file = job.dataset / "groundtruth.tum";
  job.out = root_ / "out_unwritable";
  job.quiet = true;
  const fs::path in_the_way = job.out / ("report.json.tmp-" + std::to_string(::getpid()));
  fs::create_directories(in_the_way);
  try {
    RunReconstruct(job);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find((job.out / "report.json").string()), std::string::npos)
        << e.what();
  }
  std::vector<fs::path> left;
  for (const auto& entry : fs::directory_iterator(job.out)) left.push_back(entry.path());
  EXPECT_EQ(left, std::vector<fs::path>{in_the_way});
}

// Ctrl-C in the middle of a scan (here raised by the pose provider at the
// third frame) stops it like an error: no folder, no temporary file left.
TEST_F(ReconstructTest, CtrlCLeavesNothingBehind) {
  struct RaisingProvider : fusion::PoseProvider {
    std::vector<fusion::PoseUpdate> Add(const fusion::FrameInput& frame) override {
      if (++frames == 3) std::raise(SIGINT);
      return {{frame.index, Rigid3d()}};
    }
    std::string Name() const override { return "raising"; }
    int frames = 0;
  };
  std::signal(SIGINT, SIG_DFL);  // as from a terminal
  ReconstructJob job;
  job.dataset = root_ / "data";
  job.out = root_ / "interrupted" / "out";
  job.quiet = true;
  try {
    RunReconstruct(job, std::make_unique<RaisingProvider>());
    FAIL() << "not interrupted";
  } catch (const Interrupted& e) {
    EXPECT_EQ(e.signal(), SIGINT);
  }
  EXPECT_FALSE(fs::exists(root_ / "interrupted"));
}

}  // namespace
}  // namespace uwscan
