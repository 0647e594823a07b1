// The report's warnings: what degraded a reconstruction and why, in words
// a user can act on (ReconstructReport::Warnings), and report.json; the
// job's checks of how to read an external trajectory, and its options
// resolved from the frame rate.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "uwscan/fusion/pose_smoother.h"
#include "uwscan/geometry/sim3_alignment.h"
#include "uwscan/io/dataset.h"
#include "uwscan/laser/detector.h"
#include "uwscan/pipeline/reconstruct.h"
#include "uwscan/sim/motion.h"
#include "uwscan/sim/scenario.h"
#include "uwscan/util/error.h"

namespace uwscan {
namespace {

// The report says why a result degraded (turbid water: no line, short
// profiles, short-lived features, losses), and nothing when all went well.
TEST(ReconstructReportTest, WarningsSayWhatDegradedTheResult) {
  ReconstructReport good;
  good.frames = 200;
  good.frames_with_line = 200;
  good.points = 200 * 400;
  good.scan_lines = 480;
  good.pose_details = {{"tracked", 200}, {"keyframes", 3}, {"lost", 0}};
  EXPECT_TRUE(good.Warnings().empty());

  ReconstructReport turbid = good;
  turbid.frames_with_line = 104;
  turbid.points = 104 * 13;
  turbid.frames_without_pose = 1;
  turbid.pose_details = {
      {"tracked", 199}, {"keyframes", 199}, {"lost", 1}, {"implausible_poses_rejected", 1}};
  const auto warnings = turbid.Warnings();
  ASSERT_EQ(warnings.size(), 6u);
  EXPECT_NE(warnings[0].find("no laser line in 48 %"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[1].find("13 points per frame of 480"), std::string::npos) << warnings[1];
  EXPECT_NE(warnings[2].find("1 frame(s)"), std::string::npos) << warnings[2];
  EXPECT_NE(warnings[3].find("lost 1 time(s)"), std::string::npos) << warnings[3];
  EXPECT_NE(warnings[4].find("short-lived"), std::string::npos) << warnings[4];
  EXPECT_NE(warnings[5].find("rejected"), std::string::npos) << warnings[5];
  const nlohmann::json json = turbid.ToJson();
  EXPECT_EQ(json["warnings"].size(), 6u);
  ReconstructReport dropped = good;
  dropped.frame_gaps = {2, 5, 4.0 / 144.0};
  ASSERT_EQ(dropped.Warnings().size(), 1u);
  EXPECT_NE(dropped.Warnings()[0].find(
                "5 frame(s) missing from the sequence (2 gap(s) in frames.csv's timestamps, the "
                "longest 28 ms)"),
            std::string::npos)
      << dropped.Warnings()[0];
  EXPECT_EQ(dropped.ToJson()["frames_missing"], 5);
  ReconstructReport milliseconds = good;  // frames.csv in ms, read as s
  milliseconds.frame_gaps.median_step_s = 1000.0 / 144;
  ASSERT_EQ(milliseconds.Warnings().size(), 1u);
  EXPECT_EQ(milliseconds.Warnings()[0].rfind("frames.csv: the frames are 6.944 s apart", 0), 0u)
      << milliseconds.Warnings()[0];

  // Frames without a pose: held while the odometry waited to start, lost
  // by it, or outside an external trajectory's times.
  // Whether warning i of `report` holds `text` (shown if not).
  const auto says = [](const ReconstructReport& report, size_t i, const std::string& text) {
    const std::vector<std::string> warnings = report.Warnings();
    if (i < warnings.size() && warnings[i].find(text) != std::string::npos)
      return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure()
           << (i < warnings.size() ? warnings[i] : "no warning " + std::to_string(i));
  };
  ReconstructReport partial = good;
  partial.frames_without_pose = 30;
  partial.pose_source = "self-referenced visual odometry";
  ASSERT_EQ(partial.Warnings().size(), 1u);
  EXPECT_TRUE(says(partial, 0,
                   "30 frame(s) (15 %) got no pose and are left out of the cloud (tracking lost)"));
  partial.pose_details["frames_without_pose_at_start"] = 20;
  ASSERT_EQ(partial.Warnings().size(), 2u);
  EXPECT_TRUE(
      says(partial, 0, "20 frame(s) (10 %) got no pose while the odometry waited to start"));
  EXPECT_EQ(partial.Warnings()[0].find("too narrow"), std::string::npos);
  EXPECT_TRUE(says(partial, 1,
                   "10 frame(s) (5 %) got no pose and are left out of the cloud (tracking lost)"));
  partial.pose_details["frames_without_pose_at_start"] = 30;
  partial.pose_details["start_attempts_refused"] = 9;
  ASSERT_EQ(partial.Warnings().size(), 1u);
  EXPECT_TRUE(says(partial, 0,
                   "9 start attempt(s) found the held frames' profiles too narrow once tracked"));
  EXPECT_EQ(partial.Warnings()[0].find("diverge"), std::string::npos);
  partial.pose_details["start_attempts_refused_unsettled"] = 1;
  EXPECT_TRUE(says(partial, 0,
                   "platform moved with the sweep (1 of them because the held frames' poses "
                   "began to diverge before they settled)"));
  partial.pose_source = "ins.tum";
  EXPECT_TRUE(says(partial, 0, "(ins.tum has none at their times)"));

  // The line in another colour than rig.yaml's wavelength gives: first.
  ReconstructReport red = good;
  red.frames_with_line = 10;
  red.laser_seen_in = "red";
  red.laser_colour_warning = laser::LaserColourWarning(laser::kRed, laser::kGreen, 532);
  ASSERT_EQ(red.Warnings().size(), 2u);  // with: no line in most frames
  EXPECT_TRUE(says(red, 0,
                   "the laser line shows in red, not in green, the colour of its 532 nm in "
                   "rig.yaml: set the laser's wavelength_nm to its own"));

  // Line points that met the light sheet nowhere: a few are no doubt (5 %
  // of the line's points are), and a pose whose inverse fits is named.
  ReconstructReport missed = good;
  missed.triangulation_failures = 4000;
  EXPECT_TRUE(missed.Warnings().empty());
  missed.triangulation_failures = 4300;
  ASSERT_EQ(missed.Warnings().size(), 1u);
  EXPECT_TRUE(says(missed, 0,
                   "4300 line point(s) (5 %) met the laser's light sheet nowhere in front of "
                   "the camera and are left out: the laser's pose or bend in rig.yaml does not "
                   "match the line seen"));
  missed.laser_pose_inverse_fits = true;
  EXPECT_TRUE(says(missed, 0, "the laser's pose in rig.yaml looks inverted"));

  // --poses: an INS's 100 Hz log holds no doubt; one whose steps are seconds
  // (a log in milliseconds) or of which the frames hold fewer than two does.
  ReconstructReport external = good;
  external.pose_source = "ins.tum";
  external.sequence_duration_s = 1.4;
  external.external_pose_step_s = 0.01;
  external.external_poses_in_scan = 140;
  EXPECT_TRUE(external.Warnings().empty());
  external.external_pose_step_s = 6.94;
  external.external_poses_in_scan = 1;
  ASSERT_EQ(external.Warnings().size(), 1u);
  EXPECT_TRUE(says(external, 0,
                   "ins.tum's poses are 6.94 s apart (median), and the frames' 1.4 s hold 1 of "
                   "them: every profile is placed with a pose interpolated over that, whatever "
                   "the platform did between (are its times in milliseconds? divide them by "
                   "1000)"));
  external.external_pose_step_s = 0.5;  // a 2 Hz log and a short scan
  EXPECT_TRUE(says(external, 0, "0.5 s apart (median), and the frames' 1.4 s hold 1 of them"));
  EXPECT_EQ(external.Warnings()[0].find("milliseconds"), std::string::npos);

  // Marine snow: the particles the colour test ignored are named, and with
  // the self-referenced poses in many frames what they do to the odometry.
  ReconstructReport snowy = good;
  snowy.frames_with_off_colour = 9;
  snowy.off_colour_points = 80;
  snowy.pose_source = "self-referenced visual odometry";
  ASSERT_EQ(snowy.Warnings().size(), 1u);
  EXPECT_NE(snowy.Warnings()[0].find("80 candidates"), std::string::npos);
  EXPECT_EQ(snowy.Warnings()[0].find("scale"), std::string::npos);  // 9 of 200 frames
  snowy.frames_with_off_colour = 10;
  EXPECT_NE(snowy.Warnings()[0].find("scale to be off"), std::string::npos);
  snowy.pose_source = "external trajectory";
  EXPECT_EQ(snowy.Warnings()[0].find("scale"), std::string::npos);

  // An exposure that clips the features' colour: on a tenth of the frames
  // examined or more, each with 5 % of that colour at full scale.
  ReconstructReport bright = good;
  bright.frames_features_clipping_examined = 200;
  bright.frames_with_clipped_features = 19;
  bright.features_clipped_samples = 1200;
  bright.features_clipping_samples_examined = 48000;
  bright.features_colour = "red";
  EXPECT_TRUE(bright.Warnings().empty());
  bright.frames_with_clipped_features = 20;
  ASSERT_EQ(bright.Warnings().size(), 1u);
  EXPECT_TRUE(says(bright, 0,
                   "in 20 frame(s) the features' colour (red, lit by the floods) is at full "
                   "scale on 5 % or more of the image (2.5 % over all frames)"));
  EXPECT_TRUE(says(bright, 0, "lower the camera's exposure or gain"));
  EXPECT_EQ(bright.ToJson()["frames_with_clipped_features"], 20);
  EXPECT_DOUBLE_EQ(bright.ToJson()["clipped_features_share"].get<double>(), 0.025);
  EXPECT_EQ(bright.ToJson()["features_colour"], "red");

  // A start that had not settled: a few millimetres off may only bend the
  // start; ten times the tolerance off, the features did not hold the
  // scene still and the whole trajectory may be off (turbid water). On a
  // servo sweep either way a tracked image that can be halved is run again
  // on half of it.
  ReconstructReport unsettled = good;
  unsettled.pose_details["start_settled"] = false;
  unsettled.pose_details["start_refinements"] = 3;
  unsettled.pose_details["start_settled_within_mm"] = 2.0;
  unsettled.pose_details["start_last_change_mm"] = 19.3;
  ASSERT_EQ(unsettled.Warnings().size(), 1u);
  EXPECT_TRUE(says(unsettled, 0, "(their poses still moved 19.3 mm rms): the start of the"));
  EXPECT_EQ(unsettled.Warnings()[0].find("whole trajectory"), std::string::npos);
  EXPECT_EQ(unsettled.Warnings()[0].find("--max-tracking-width"), std::string::npos);
  // Still turning while it barely moved: the turn is said too.
  unsettled.pose_details["start_settled_within_deg"] = 0.05;
  unsettled.pose_details["start_last_change_mm"] = 0.4;
  unsettled.pose_details["start_last_change_deg"] = 0.13;
  EXPECT_TRUE(says(unsettled, 0, "(their poses still moved 0.4 mm and turned 0.13 deg rms)"));
  unsettled.pose_details["start_last_change_deg"] = 0.01;
  EXPECT_TRUE(says(unsettled, 0, "(their poses still moved 0.4 mm rms)"));
  // No refinement tracked a held frame the one before had (null): no
  // "moved 0.0 mm", and no run again on half the image.
  unsettled.pose_details["start_last_change_mm"] = nullptr;
  unsettled.pose_details["start_last_change_deg"] = nullptr;
  unsettled.pose_details["tracked_image_width"] = 640;
  ASSERT_EQ(unsettled.Warnings().size(), 1u);
  EXPECT_TRUE(says(unsettled, 0,
                   "had not settled after 3 refinements: the odometry lost the held frames each "
                   "time it tracked them again, so no two refinements could be compared"));
  EXPECT_EQ(unsettled.Warnings()[0].find("mm"), std::string::npos);
  EXPECT_EQ(unsettled.SmallerTrackingWidth(), std::nullopt);
  unsettled.pose_details.erase("tracked_image_width");
  unsettled.pose_details.erase("start_last_change_deg");
  unsettled.pose_details["start_last_change_mm"] = 22.2;
  ASSERT_EQ(unsettled.Warnings().size(), 1u);
  EXPECT_TRUE(says(unsettled, 0, "still moved 22.2 mm rms, more than ten times the 2 mm"));
  EXPECT_TRUE(says(unsettled, 0, "the whole trajectory rests on that start"));
  // A tracked image that can still be halved (not below 320 px): say so.
  EXPECT_EQ(unsettled.Warnings()[0].find("--max-tracking-width"), std::string::npos);
  unsettled.pose_details["tracked_image_width"] = 640;
  EXPECT_TRUE(says(unsettled, 0,
                   "better); a smaller tracked image averages more of the "
                   "sensor's noise: try --max-tracking-width 320"));
  // With a fixed laser the held frames span the platform's motion: near
  // settled, no smaller image.
  unsettled.pose_details["start_last_change_mm"] = 19.3;
  EXPECT_FALSE(unsettled.laser_sweeps);
  EXPECT_EQ(unsettled.Warnings()[0].find("--max-tracking-width"), std::string::npos);
  EXPECT_EQ(unsettled.SmallerTrackingWidth(), std::nullopt);
  // On a servo sweep (the platform hovers) a start still moving by more
  // than its tolerance is the tracks' noise: said, and run again on half
  // the image (not below 320 px).
  unsettled.laser_sweeps = true;
  EXPECT_TRUE(says(unsettled, 0,
                   "(their poses still moved 19.3 mm rms): the start of the trajectory may be "
                   "off"));
  EXPECT_TRUE(says(unsettled, 0,
                   "--max-init-refinements); a smaller tracked image averages more of the "
                   "sensor's noise: try --max-tracking-width 320"));
  EXPECT_EQ(unsettled.SmallerTrackingWidth(), 320);  // 19.3 mm
  unsettled.pose_details["start_last_change_mm"] = 2.5;
  EXPECT_EQ(unsettled.SmallerTrackingWidth(), 320);
  EXPECT_EQ(unsettled.ToJson()["laser_sweeps"], true);
  // Within its 2 mm (still turning, say): not moving, no run again.
  unsettled.pose_details["start_last_change_mm"] = 1.9;
  EXPECT_EQ(unsettled.SmallerTrackingWidth(), std::nullopt);
  EXPECT_EQ(unsettled.Warnings()[0].find("--max-tracking-width"), std::string::npos);
  // A surface in front (a shaft before a hull) needs the full image: only
  // far from settled.
  unsettled.pose_details["start_last_change_mm"] = 19.3;
  unsettled.surface_in_front = true;
  EXPECT_EQ(unsettled.SmallerTrackingWidth(), std::nullopt);
  unsettled.surface_in_front = false;
  unsettled.laser_sweeps = false;
  // Far from settled, with either laser: run again on half the image.
  unsettled.pose_details["start_last_change_mm"] = 22.2;
  EXPECT_EQ(unsettled.SmallerTrackingWidth(), 320);
  unsettled.pose_details["tracked_image_width"] = 1280;
  EXPECT_EQ(unsettled.SmallerTrackingWidth(), 640);
  unsettled.pose_details["tracked_image_width"] = 480;
  EXPECT_EQ(unsettled.SmallerTrackingWidth(), std::nullopt);
  unsettled.tracking_retried_from_width = 640;
  unsettled.retried_start_change_mm = 42.4;
  EXPECT_TRUE(says(unsettled, 1,
                   "the start had not settled tracking the image at 640 px (its poses still "
                   "moved 42.4 mm rms): the odometry ran again at 320 px"));
  EXPECT_EQ(unsettled.ToJson()["tracking_retried_from_width"], 640);
  unsettled.tracking_retried_from_width = 0;
  unsettled.tracking_retry_failed = "D: no frame got a pose";
  EXPECT_TRUE(says(unsettled, 1,
                   "run again on half the tracked image, the odometry failed (D: no frame got "
                   "a pose): these outputs are the first run's"));
  EXPECT_EQ(unsettled.ToJson()["tracking_retry_failed"], "D: no frame got a pose");
  unsettled.tracking_retry_failed.clear();
  unsettled.pose_details["start_settled"] = true;
  EXPECT_EQ(unsettled.SmallerTrackingWidth(), std::nullopt);
  EXPECT_TRUE(unsettled.Warnings().empty());

  // Auto passes (a surface in front of the main one) that stopped before
  // the trajectory settled: said, with the last pass's move; settled, or
  // a forced count (passes_settled unset), nothing.
  ReconstructReport passes = good;
  passes.passes = 6;
  passes.pass_changes = {{0.4, 10.0}, {0.08, 3.0}, {0.008, 0.2}, {0.0061, 0.1}, {0.0052, 0.08}};
  passes.passes_settled = false;
  passes.passes_settled_within = {0.002, 0.05};
  EXPECT_TRUE(says(passes, 0,
                   "the trajectory had not settled after 6 passes: the last moved it by 5.2 mm "
                   "and 0.08 deg rms (settled: below 2 mm and 0.05 deg)"));
  const nlohmann::json passes_json = passes.ToJson();
  ASSERT_EQ(passes_json["pass_changes_mm"].size(), 5u);
  EXPECT_DOUBLE_EQ(passes_json["pass_changes_mm"][2].get<double>(), 8.0);
  EXPECT_DOUBLE_EQ(passes_json["pass_changes_deg"][4].get<double>(), 0.08);
  EXPECT_EQ(passes_json["passes_settled"], false);
  passes.passes_settled = true;
  EXPECT_TRUE(passes.Warnings().empty());
  EXPECT_EQ(passes.ToJson()["passes_settled"], true);
  passes.passes_settled.reset();
  EXPECT_TRUE(passes.Warnings().empty());
  EXPECT_TRUE(passes.ToJson()["passes_settled"].is_null());
  EXPECT_TRUE(good.ToJson()["pass_changes_mm"].empty());

  // Points whose ray grazes the sheet: a few are stray light, silently
  // dropped (in report.json); from 1 % of the points on, a warning.
  ReconstructReport grazing = good;
  grazing.max_range_error_per_px = 0.05;
  grazing.grazing_points = grazing.points / 100 - 1;
  EXPECT_TRUE(grazing.Warnings().empty());
  EXPECT_EQ(grazing.ToJson()["grazing_points_dropped"], grazing.points / 100 - 1);
  grazing.grazing_points = grazing.points / 50;
  ASSERT_EQ(grazing.Warnings().size(), 1u);
  EXPECT_NE(grazing.Warnings()[0].find("by more than 5 % of their range"), std::string::npos)
      << grazing.Warnings()[0];

  // No frame placed: the profiles are not short, there are none in the cloud.
  ReconstructReport unposed = good;
  unposed.points = 0;
  unposed.frames_without_pose = 200;
  const auto unposed_warnings = unposed.Warnings();
  ASSERT_FALSE(unposed_warnings.empty());
  for (const auto& w : unposed_warnings)
    EXPECT_EQ(w.find("profiles are short"), std::string::npos) << w;
}

// --poses-body-from-camera: seven numbers in TUM's order, a unit quaternion.
TEST(ReconstructJobTest, PosesOfAnotherBodyAndClockAreReadOrRefused) {
  const Rigid3d pose = ParseBodyFromCamera("0.3,-0.1,0.2,0,0,0.7071068,0.7071068");
  EXPECT_NEAR((pose.translation - Eigen::Vector3d(0.3, -0.1, 0.2)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((pose.rotation * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm(), 0.0,
              1e-6);  // 90 deg about z
  for (const std::string bad : {"", "1,2,3", "0,0,0,0,0,0,1,", "0,0,0,0,0,0,x", "0,0,0,0,0,0,1,0",
                                "0,0,0,0,0,0,nan", "0,0,0,0,0,0,2"})
    EXPECT_THROW(ParseBodyFromCamera(bad), UsageError) << bad;
  try {
    ParseBodyFromCamera("0,0,0,0,0,0,2");
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("unit quaternion, its norm is 2"), std::string::npos)
        << e.what();
  }
  ReconstructJob job;
  job.dataset = "D";
  job.out = "O";
  job.poses_time_offset_s = 0.5;
  EXPECT_THROW(job.Check(), UsageError);  // without --poses
  job.poses_file = "ins.tum";
  EXPECT_NO_THROW(job.Check());
  job.poses_time_offset_s = std::nan("");
  EXPECT_THROW(job.Check(), UsageError);
  job.poses_time_offset_s = 0.0;
  job.poses_body_from_camera = Rigid3d();
  job.poses_file.reset();
  EXPECT_THROW(job.Check(), UsageError);
}

// `count` frames at `rate_hz`, from 3 s on.
std::vector<FrameRecord> FramesAt(double rate_hz, int count) {
  std::vector<FrameRecord> frames(count);
  for (int i = 0; i < count; ++i) frames[i].timestamp_s = 3.0 + i / rate_hz;
  return frames;
}

// --track-every auto: the fewest N that keep the tracked rate at or below
// 100 Hz; a count given is kept.
TEST(ReconstructTrackEvery, AutoFollowsTheFrameRate) {
  EXPECT_EQ(ResolveTrackEvery(0, FramesAt(144.0, 50)), 2);
  EXPECT_EQ(ResolveTrackEvery(0, FramesAt(100.0, 50)), 1);
  EXPECT_EQ(ResolveTrackEvery(0, FramesAt(50.0, 50)), 1);
  EXPECT_EQ(ResolveTrackEvery(0, FramesAt(15.0, 50)), 1);
  EXPECT_EQ(ResolveTrackEvery(0, FramesAt(250.0, 50)), 3);
  EXPECT_EQ(ResolveTrackEvery(0, FramesAt(144.0, 1)), 1);
  EXPECT_EQ(ResolveTrackEvery(0, std::vector<FrameRecord>(5)), 1);  // no time between frames
  EXPECT_EQ(ResolveTrackEvery(3, FramesAt(50.0, 50)), 3);
  EXPECT_EQ(ResolveTrackEvery(1, FramesAt(144.0, 50)), 1);
  EXPECT_EQ(ParseTrackEvery("auto"), 0);
  EXPECT_EQ(ParseTrackEvery("2"), 2);
  for (const char* bad : {"0", "-1", "2x", "", "two"})
    EXPECT_THROW(ParseTrackEvery(bad), UsageError) << bad;
  // A refused start's screen: at most 40 held frames tracked per second,
  // and at least every track_every-th; a count given is kept.
  EXPECT_EQ(ResolveStartScreenEvery(0, 2, FramesAt(144.0, 50)), 4);
  EXPECT_EQ(ResolveStartScreenEvery(0, 1, FramesAt(144.0, 50)), 4);
  EXPECT_EQ(ResolveStartScreenEvery(0, 1, FramesAt(50.0, 50)), 2);
  EXPECT_EQ(ResolveStartScreenEvery(0, 1, FramesAt(40.0, 50)), 1);
  EXPECT_EQ(ResolveStartScreenEvery(0, 1, FramesAt(15.0, 50)), 1);
  EXPECT_EQ(ResolveStartScreenEvery(0, 6, FramesAt(144.0, 50)), 6);
  EXPECT_EQ(ResolveStartScreenEvery(0, 2, std::vector<FrameRecord>(5)), 2);
  EXPECT_EQ(ResolveStartScreenEvery(2, 2, FramesAt(144.0, 50)), 2);
  try {
    ParseTrackEvery("0", "--start-screen-every");
    ADD_FAILURE() << "0 accepted";
  } catch (const UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("--start-screen-every"), std::string::npos) << e.what();
  }
  // The windowed BA goes to a second thread where frames are skipped.
  EXPECT_TRUE(ResolveAsyncBundleAdjustment(std::nullopt, FramesAt(144.0, 50)));
  EXPECT_FALSE(ResolveAsyncBundleAdjustment(std::nullopt, FramesAt(100.0, 50)));
  EXPECT_FALSE(ResolveAsyncBundleAdjustment(std::nullopt, FramesAt(50.0, 50)));
  EXPECT_FALSE(ResolveAsyncBundleAdjustment(std::nullopt, FramesAt(144.0, 1)));
  EXPECT_FALSE(ResolveAsyncBundleAdjustment(false, FramesAt(144.0, 50)));
  EXPECT_TRUE(ResolveAsyncBundleAdjustment(true, FramesAt(15.0, 50)));
}

// --smoothing-half-window auto: 10 frames (69 ms at the thesis camera's
// 144 Hz), but no more than the frames within 0.14 s (10 frames of a
// 50 Hz camera span 0.2 s of a hover's motion, which the quadratic fit
// bends: AutoWindowKeepsTheHoversMotion); a count given is kept.
TEST(ReconstructSmoothing, AutoSpansAtMostAboutASeventhOfASecond) {
  EXPECT_EQ(ResolveSmoothingHalfWindow(std::nullopt, FramesAt(144.0, 50)), 10);
  EXPECT_EQ(ResolveSmoothingHalfWindow(std::nullopt, FramesAt(250.0, 50)), 10);
  EXPECT_EQ(ResolveSmoothingHalfWindow(std::nullopt, FramesAt(72.0, 50)), 10);
  EXPECT_EQ(ResolveSmoothingHalfWindow(std::nullopt, FramesAt(50.0, 50)), 7);
  EXPECT_EQ(ResolveSmoothingHalfWindow(std::nullopt, FramesAt(48.0, 50)), 7);
  EXPECT_EQ(ResolveSmoothingHalfWindow(std::nullopt, FramesAt(30.0, 50)), 4);
  EXPECT_EQ(ResolveSmoothingHalfWindow(std::nullopt, FramesAt(28.8, 50)), 4);
  EXPECT_EQ(ResolveSmoothingHalfWindow(std::nullopt, FramesAt(15.0, 50)), 2);
  EXPECT_EQ(ResolveSmoothingHalfWindow(std::nullopt, FramesAt(5.0, 50)), 1);
  EXPECT_EQ(ResolveSmoothingHalfWindow(std::nullopt, FramesAt(2.0, 50)), 0);  // raw
  EXPECT_EQ(ResolveSmoothingHalfWindow(std::nullopt, FramesAt(28.8, 1)), 10);
  EXPECT_EQ(ResolveSmoothingHalfWindow(std::nullopt, std::vector<FrameRecord>(5)), 10);
  EXPECT_EQ(ResolveSmoothingHalfWindow(10, FramesAt(28.8, 50)), 10);
  EXPECT_EQ(ResolveSmoothingHalfWindow(2, FramesAt(28.8, 50)), 2);
  EXPECT_EQ(ResolveSmoothingHalfWindow(0, FramesAt(144.0, 50)), 0);
  EXPECT_EQ(ParseSmoothingHalfWindow("auto"), std::nullopt);
  EXPECT_EQ(ParseSmoothingHalfWindow("0"), 0);
  EXPECT_EQ(ParseSmoothingHalfWindow("12"), 12);
  for (const char* bad : {"-1", "2x", "", "ten"})
    EXPECT_THROW(ParseSmoothingHalfWindow(bad), UsageError) << bad;
}

// The auto window on the simulator's own hover (the tank scan's motion,
// no tracking noise): smoothed, the true poses must keep their motion. A
// quadratic fit over too long a span flattens the hover's turns, and the
// trajectory then comes out smaller than the truth: with the frames within
// 0.2 s, the tank scans at 14.4-48 Hz came out 0.2-0.5 % small and their
// board's distance error grew by half (BENCHMARKS.md, "The pose smoothing
// over 0.14 s").
TEST(ReconstructSmoothing, AutoWindowKeepsTheHoversMotion) {
  for (const double rate_hz : {14.4, 28.8, 48.0, 50.0, 72.0, 144.0}) {
    const auto frames = FramesAt(rate_hz, static_cast<int>(std::lround(14.0 * rate_hz)));
    const int half_window = ResolveSmoothingHalfWindow(std::nullopt, frames);
    double worst_scale_error = 0.0, worst_rms_m = 0.0;
    for (const uint64_t seed : {1, 2, 3, 4, 5}) {
      sim::ScenarioOptions options;
      options.seed = seed;
      const sim::Trajectory truth(sim::MakeScenario("tank-target", options).motion);
      fusion::PoseSmoother smoother(half_window);
      std::vector<fusion::PoseUpdate> smoothed;
      for (size_t i = 0; i < frames.size(); ++i) {
        const auto out =
            smoother.Add({static_cast<int>(i), truth.WorldFromCamera(frames[i].timestamp_s)},
                         frames[i].timestamp_s);
        smoothed.insert(smoothed.end(), out.begin(), out.end());
      }
      const auto rest = smoother.Flush();
      smoothed.insert(smoothed.end(), rest.begin(), rest.end());
      ASSERT_EQ(smoothed.size(), frames.size());
      std::vector<Eigen::Vector3d> estimate, reference;
      double sum_squares = 0.0;
      for (const auto& pose : smoothed) {
        estimate.push_back(pose.world_from_camera.translation);
        reference.push_back(truth.WorldFromCamera(frames[pose.frame].timestamp_s).translation);
        sum_squares += (estimate.back() - reference.back()).squaredNorm();
      }
      const auto alignment = AlignSim3(estimate, reference);
      ASSERT_TRUE(alignment.has_value());
      worst_scale_error = std::max(worst_scale_error, std::abs(alignment->scale - 1.0));
      worst_rms_m = std::max(worst_rms_m, std::sqrt(sum_squares / smoothed.size()));
    }
    std::printf("%.1f Hz, +-%d frames: scale off by %.4f %%, %.4f mm rms at most\n", rate_hz,
                half_window, 100.0 * worst_scale_error, 1e3 * worst_rms_m);
    // Within 0.2 s: 0.33-0.48 % and 0.17-0.25 mm at 14.4-50 Hz.
    EXPECT_LT(worst_scale_error, 1.5e-3) << rate_hz << " Hz";
    EXPECT_LT(worst_rms_m, 0.075e-3) << rate_hz << " Hz";
  }
}

// --max-start-plane-angle: the view cosine the start's plane must reach
// (60 deg by default, SelfReferencedOptions' 0.5; 90 = any plane).
TEST(ReconstructStartPlane, TheLargestAngleIsTheViewCosine) {
  EXPECT_NEAR(DefaultMaxStartPlaneAngleDeg(), 60.0, 1e-9);
  EXPECT_NEAR(StartPlaneViewCosine(DefaultMaxStartPlaneAngleDeg()),
              fusion::SelfReferencedOptions().min_start_plane_view_cosine, 1e-12);
  EXPECT_NEAR(StartPlaneViewCosine(45.0), std::sqrt(0.5), 1e-12);
  EXPECT_EQ(StartPlaneViewCosine(90.0), 0.0);
  for (const double bad : {0.0, -10.0, 90.5, std::nan("")})
    EXPECT_THROW(StartPlaneViewCosine(bad), UsageError) << bad;
}

// --log-offset: 0 (linear) up to 100 times the image's mean; else a usage
// error that names the flag.
TEST(ReconstructLogOffset, OutOfRangeIsAUsageError) {
  ReconstructJob job;
  job.dataset = "d";
  job.out = "o";
  for (const double good : {0.0, 0.5, fusion::SelfReferencedOptions::kMaxLogOffsetFraction}) {
    job.self_referenced.log_offset_fraction = good;
    EXPECT_NO_THROW(job.Check()) << good;
  }
  for (const double bad : {-0.1, 100.5, std::nan("")}) {
    job.self_referenced.log_offset_fraction = bad;
    try {
      job.Check();
      ADD_FAILURE() << bad << " accepted";
    } catch (const UsageError& e) {
      EXPECT_NE(std::string(e.what()).find("--log-offset"), std::string::npos) << e.what();
    }
  }
}

// A live run's lags: the largest and when its frame came, the median, the
// last, and at each whole second the lag of the last frame delivered by
// then (none before the first placed frame, the one before if none came
// since).
TEST(ReconstructLive, LagsSummarisedOverTheScan) {
  EXPECT_FALSE(SummarizeLiveLag({}, 5.0).has_value());
  const std::vector<std::pair<double, double>> lags = {
      {1.5, 3.0}, {1.6, 2.9}, {2.2, 2.5}, {4.1, 0.4}, {4.5, 0.3}};
  const auto live = SummarizeLiveLag(lags, 5.2);
  ASSERT_TRUE(live.has_value());
  EXPECT_EQ(live->max_s, 3.0);
  EXPECT_EQ(live->max_at_scan_s, 1.5);
  EXPECT_EQ(live->median_s, 2.5);
  EXPECT_EQ(live->last_s, 0.3);
  ASSERT_EQ(live->at_each_second_s.size(), 5u);
  EXPECT_FALSE(live->at_each_second_s[0].has_value());
  EXPECT_EQ(live->at_each_second_s[1], 2.9);
  EXPECT_EQ(live->at_each_second_s[2], 2.5);
  EXPECT_EQ(live->at_each_second_s[3], 2.5);
  EXPECT_EQ(live->at_each_second_s[4], 0.3);
  const nlohmann::json json = live->ToJson();
  EXPECT_TRUE(json["at_each_second"][0].is_null());
  EXPECT_EQ(json["at_each_second"][4].get<double>(), 0.3);
}

// A live run is processed once, as the camera delivers it: more passes or
// a retry on half the image would read the frames again.
TEST(ReconstructLive, NeedsOnePassAndNoRetry) {
  ReconstructJob job;
  job.dataset = "data";
  job.out = "out";
  job.live = true;
  EXPECT_THROW(job.Check(), UsageError);  // passes auto
  job.passes = 1;
  EXPECT_THROW(job.Check(), UsageError);  // retry on half the image
  job.retry_smaller_tracking = false;
  EXPECT_NO_THROW(job.Check());
}

}  // namespace
}  // namespace uwscan
