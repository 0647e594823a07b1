// Scans with more than one camera or more than one pass of the
// odometry: the two-pod vehicle of §6.5 and a shaft in front of a hull.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "uwscan/fusion/pose_provider.h"
#include "uwscan/io/dataset.h"
#include "uwscan/io/ply.h"
#include "uwscan/io/rig_yaml.h"
#include "uwscan/io/tum.h"
#include "uwscan/pipeline/evaluate_reconstruction.h"
#include "uwscan/pipeline/reconstruct.h"
#include "uwscan/pipeline/testing.h"
#include "uwscan/sim/simulate.h"
#include "uwscan/util/error.h"
#include "uwscan/util/interrupt.h"

namespace uwscan {
namespace {
namespace fs = std::filesystem;
using namespace pipeline_testing;

// The two-pod vehicle of §6.5: camera 1 (images in DATA/cam1/) uses the
// laser of pod 0 and its profiles join the cloud, placed with camera 0's
// poses through the rig. They land on the true floor and target, and they
// reach beyond where camera 0's line sweeps.
TEST(ReconstructTwoPods, TheSecondCamerasProfilesJoinTheCloud) {
  const fs::path root = TempFolder("two_pods");
  sim::ScenarioOptions options = ScanOptions(480, 360, 20, 35);
  options.pods = 2;
  ReconstructJob job = SimulatedJob(root, "tank-target", options);
  ASSERT_TRUE(fs::exists(root / "data" / "cam1" / "frames.csv"));
  job.poses_file = job.dataset / "groundtruth.tum";
  job.out = root / "both";
  const ReconstructReport report = RunReconstruct(job);
  ASSERT_EQ(report.other_cameras.size(), 1u);
  const CameraReport& second = report.other_cameras.front();
  EXPECT_EQ(second.name, "cam1");
  EXPECT_EQ(second.laser, "laser1");
  EXPECT_EQ(second.frames, 20);
  EXPECT_EQ(second.frames_without_pose, 0);
  EXPECT_GT(second.points, 20 * 100);
  EXPECT_TRUE(fs::exists(job.out / "trajectory_cam1.tum"));

  // Independently of the evaluation: the true world is the floor (z = 0)
  // and the target (z = 5 mm) here, the poses being the true ones.
  double max_x[2] = {-1e9, -1e9};
  long on_scene[2] = {0, 0}, count[2] = {0, 0};
  for (const CloudPoint& point : ReadPly(job.out / "cloud.ply")) {
    const int camera = point.frame >= 20;
    ++count[camera];
    const double z = point.position.z();
    on_scene[camera] += std::min(std::abs(z), std::abs(z - 0.005)) < 0.005;
    max_x[camera] = std::max(max_x[camera], point.position.x());
  }
  EXPECT_EQ(count[1], second.points);
  EXPECT_GT(on_scene[0], 0.97 * count[0]);
  EXPECT_GT(on_scene[1], 0.97 * count[1]);
  EXPECT_GT(max_x[1], max_x[0] + 0.1);
  const auto evaluation = EvaluateReconstruction(job.dataset, job.out);
  EXPECT_GT(evaluation.compensated.matched, report.points * 95 / 100);
  EXPECT_LT(evaluation.compensated.point_error_rms_m, 0.002);
  EXPECT_GT(evaluation.uncompensated.point_error_rms_m,
            2.0 * evaluation.compensated.point_error_rms_m);
  // Each of camera 1's poses is the main trajectory's at its time, moved
  // through the rig (checked here from the outputs).
  {
    const auto main_trajectory = ReadTum(job.out / "trajectory.tum");
    const auto second_frames = ReadFramesCsv(job.dataset / "cam1" / "frames.csv");
    const auto second_trajectory = ReadTum(job.out / "trajectory_cam1.tum");
    const Rigid3d main_from_second = ReadRigYaml(job.dataset / "rig.yaml").CameraFromCamera(0, 1);
    ASSERT_EQ(second_trajectory.size(), second_frames.size());
    for (size_t k = 0; k < second_frames.size(); ++k) {
      const auto main = fusion::InterpolatePose(main_trajectory, second_frames[k].timestamp_s, 1.0);
      ASSERT_TRUE(main.has_value());
      const Rigid3d expected = *main * main_from_second;
      const Rigid3d& placed = second_trajectory[k].world_from_camera;
      EXPECT_LT((expected.translation - placed.translation).norm(), 1e-6) << k;
      EXPECT_LT(expected.rotation.angularDistance(placed.rotation), 1e-6) << k;
    }
  }
  // Camera 1's profiles join the cloud as the main trajectory reaches
  // their times, not after the main camera's whole scan (a live cloud
  // grows from both cameras at once): in the file, camera 1's frame k
  // (numbered 20 + k) comes before camera 0's frame k + 3.
  const auto joined_as_the_scan_went = [](const fs::path& cloud) {
    std::map<int, size_t> first_at;  // frame -> its first point's place in the file
    size_t at = 0;
    for (const CloudPoint& point : ReadPly(cloud)) first_at.emplace(point.frame, at++);
    int compared = 0;
    for (int k = 0; k + 3 < 20; ++k) {
      if (!first_at.count(20 + k) || !first_at.count(k + 3)) continue;
      ++compared;
      if (first_at[20 + k] > first_at[k + 3]) return false;
    }
    return compared >= 10;
  };
  EXPECT_TRUE(joined_as_the_scan_went(job.out / "cloud.ply"));
  EXPECT_TRUE(joined_as_the_scan_went(job.out / "cloud_uncompensated.ply"));

  // Replayed live, with the clock slowed tenfold (1.4 s): camera 1's
  // frames are delivered at the camera's pace too and join the cloud as
  // they come, their lags measured among the main camera's.
  {
    const fs::path slow = root / "slow";
    CopyWithClockStretched(job.dataset, slow, 10.0);
    ReconstructJob live_job = job;
    live_job.dataset = slow;
    live_job.poses_file = slow / "groundtruth.tum";
    live_job.out = root / "live";
    live_job.live = true;
    live_job.passes = 1;
    live_job.retry_smaller_tracking = false;
    const ReconstructReport live = RunReconstruct(live_job);
    ASSERT_EQ(live.other_cameras.size(), 1u);
    EXPECT_EQ(live.other_cameras.front().frames, 20);
    EXPECT_GT(live.other_cameras.front().points, 20 * 100);
    ASSERT_TRUE(live.live_lag.has_value());
    EXPECT_LT(live.live_lag->median_s, 0.5);
    EXPECT_TRUE(joined_as_the_scan_went(live_job.out / "cloud.ply"));
  }

  job.out = root / "main_only";
  job.other_cameras = false;
  const ReconstructReport main_only = RunReconstruct(job);
  EXPECT_TRUE(main_only.other_cameras.empty());
  EXPECT_EQ(main_only.points, report.points - second.points);
  // Camera 1's line stage counts apart (it runs on its own thread, in
  // parallel) and is added in: the scene's clipping examined on both
  // cameras' frames; the first frame inspected is still camera 0's.
  EXPECT_GT(report.frames_clipping_examined, main_only.frames_clipping_examined);
  EXPECT_EQ(report.first_frame.file, main_only.first_frame.file);
  EXPECT_EQ(report.first_frame.file.parent_path().parent_path(), job.dataset);
  // Camera 1 named on the top folder: its images are elsewhere.
  job.camera_name = "cam1";
  job.out = root / "wrong_camera";
  try {
    RunReconstruct(job);
    ADD_FAILURE() << "camera 1 on the top folder: no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("for camera 'cam1' alone give --dataset " +
                                         (job.dataset / "cam1").string()),
              std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(fs::exists(job.out));
  fs::remove_all(root);
}

// A later pass interrupted by Ctrl-C, or failing (a frame damaged), once
// the first pass has committed its outputs: those stand, whole (the
// trajectory of `one_pass`, a run of one pass on `job`'s dataset), the
// report says why the second is missing, and the interruption names them.
void CheckALaterPassThatFails(ReconstructJob job, const fs::path& root, const fs::path& one_pass) {
  const auto stands = [&](const fs::path& out) {
    EXPECT_EQ(FileBytes(out / "trajectory.tum"), FileBytes(one_pass / "trajectory.tum"));
    for (const auto& entry : fs::directory_iterator(out))
      EXPECT_EQ(entry.path().string().find(".tmp-"), std::string::npos) << entry.path();
    const nlohmann::json json = nlohmann::json::parse(std::ifstream(out / "report.json"));
    EXPECT_EQ(json["passes"], 1);
    return json["later_pass_failed"].get<std::string>();
  };
  job.passes = 0;
  job.out = root / "interrupted";
  std::signal(SIGINT, SIG_DFL);  // as from a terminal
  try {
    RunReconstructActingOnceCommitted(job, [] { std::raise(SIGINT); });
    ADD_FAILURE() << "not interrupted";
  } catch (const Interrupted& e) {
    EXPECT_EQ(e.signal(), SIGINT);
    EXPECT_NE(std::string(e.what()).find(job.out.string() + " holds pass 1's outputs"),
              std::string::npos)
        << e.what();
  }
  EXPECT_EQ(stands(job.out), "interrupted by Ctrl-C");

  job.out = root / "failed";
  fs::copy(job.dataset, root / "damaged", fs::copy_options::recursive);
  job.dataset = root / "damaged";
  const fs::path last_frame = job.dataset / ReadFramesCsv(job.dataset / "frames.csv").back().file;
  bool damaged = false;
  const ReconstructReport failed = RunReconstructActingOnceCommitted(
      job, [&] { fs::resize_file(last_frame, fs::file_size(last_frame) / 2); }, &damaged);
  ASSERT_TRUE(damaged);
  EXPECT_EQ(failed.passes, 1);
  EXPECT_NE(failed.later_pass_failed.find(last_frame.filename().string()), std::string::npos)
      << failed.later_pass_failed;
  EXPECT_EQ(stands(job.out), failed.later_pass_failed);
  EXPECT_TRUE(Warns(failed, {"pass 2 failed ("}));
  EXPECT_TRUE(Warns(failed, {"these outputs are pass 1's"}));
  EXPECT_FALSE(Warns(failed, {"without --live"}));  // auto passes did run
}

// A hull with a propeller shaft in front of it (§6.5), scanned while the
// platform moves along: the laser reaches the shaft late in the scan, so a
// single pass gives the shaft's features the hull's depth, 0.7 m too far,
// until then. The first pass finds the surface in front, so by default two
// more run (and more until the trajectory settles), each from its first
// frame on the surface the pass before measured over the whole scan; the
// shaft's cylinder then fits better than
// with the INS-like trajectory, as the issue asks (coastal water, 640x480).
// The second pass starts from the first pass's misplaced shaft, the third
// from the second pass's own profiles; whether two passes already suffice
// varies from seed to seed (on this one: 1.89 mm when the test was written,
// 0.72 mm since tracks start from their predicted positions), the third
// brings the shaft to the floor of the method either way.
TEST(ReconstructPasses, AShaftInFrontOfTheHullGetsMorePasses) {
  const fs::path root = TempFolder("passes");
  sim::ScenarioOptions options = ScanOptions(640, 480, 120, 73);
  ReconstructJob job = SimulatedJob(root, "hull", options);
  // The passes on their own: the first pass's points from the start's
  // tilted plane are not placed again on the settled one (checked at the end).
  job.self_referenced.surface.settled_plane_width_m = 0.0;
  // The same BAs on a slow or loaded machine: a failed later pass leaves the
  // one-pass run's trajectory, compared to the byte (CheckALaterPassThatFails).
  job.self_referenced.odometry.ba.max_solver_time_s = 10.0;
  const auto shaft_residual = [&job](const ReconstructReport& report) {
    const auto evaluation = EvaluateReconstruction(job.dataset, job.out);
    const SurfaceAccuracy* shaft = evaluation.compensated.Surface("shaft");
    EXPECT_NE(shaft, nullptr);
    EXPECT_GT(report.points, 10000);
    return shaft ? shaft->robust_fit_rms_m : 1e9;
  };
  const auto run = [&](const std::string& name, int passes) {
    job.out = root / name;
    job.passes = passes;
    return RunReconstruct(job);
  };
  const ReconstructReport automatic = run("auto", 0);
  EXPECT_GE(automatic.passes, 3);  // and more until the trajectory settles
  EXPECT_EQ(automatic.passes_settled, true);
  EXPECT_GT(automatic.seconds_earlier_passes, 0.0);
  EXPECT_GT(automatic.seconds, automatic.seconds_earlier_passes);
  const double auto_passes = shaft_residual(automatic);
  const ReconstructReport two = run("two", 2);
  EXPECT_EQ(two.passes, 2);
  const double two_passes = shaft_residual(two);
  const ReconstructReport one = run("one", 1);
  EXPECT_EQ(one.passes, 1);
  const double one_pass = shaft_residual(one);
  // Forced to one pass (as a live run is), the report says what the passes
  // would have mended; where they ran it has nothing to say.
  const auto says_in_front = [](const ReconstructReport& report) {
    return Warns(report, {"surface standing in front of its main one", "without --live"});
  };
  EXPECT_TRUE(one.surface_in_front);
  EXPECT_TRUE(says_in_front(one));
  EXPECT_TRUE(automatic.surface_in_front);
  EXPECT_FALSE(says_in_front(automatic));
  EXPECT_FALSE(says_in_front(two));
  CheckALaterPassThatFails(job, root, root / "one");
  job.poses_file = job.dataset / "ins.tum";
  const double ins = shaft_residual(run("ins", 0));
  std::printf(
      "shaft cylinder residual: auto (%d passes) %.2f mm, two %.2f mm, one %.2f mm, INS %.2f "
      "mm\n",
      automatic.passes, auto_passes * 1e3, two_passes * 1e3, one_pass * 1e3, ins * 1e3);
  EXPECT_LT(auto_passes, 0.5 * ins);
  // One pass and two are lotteries on this hull (one 2.43 / 1.78 / 2.54 mm,
  // two 0.38 / 0.38 / 0.48 mm against auto's 0.36 / 0.36 / 0.39 in builds
  // that differ only in the last bits of the exact projection; BENCHMARKS.md,
  // "The tests on a CPU without AVX"): auto is better than one pass and no
  // worse than two.
  EXPECT_LT(auto_passes, 0.5 * one_pass);
  EXPECT_LT(auto_passes, 1.1 * two_passes);
  // 0.36-0.38 mm here (the 31 hull sequences of BENCHMARKS.md: 0.35-0.63 mm,
  // median 0.46, but 1.26 on coastal seed 79); a third pass on the second's
  // surface mixed with the first's (the odometry's own) gave 0.65 mm.
  EXPECT_LT(auto_passes, 0.5e-3);

  // One pass, its points from the start's plane placed again once the plane
  // has settled (the default), with the odometry's options this was
  // written with (the linear tracked image, the loss at 1.5 px). When
  // written, one pass gave 11.0 mm without placing them again and 0.94 mm
  // with; builds that differ only in the last bits of the exact projection
  // gave 1.42 / 1.44 / 9.26 mm without and 0.93 / 8.13 / 0.94 mm with
  // (BENCHMARKS.md, "The exact projection in fewer Newton steps"): one pass
  // on a hull whose shaft the laser reaches late is a lottery either way
  // (0.5-30 mm on twelve more hulls), which is why auto runs more. Checked
  // here: the points are placed again (their effect on a floor is checked
  // in self_referenced_test).
  job.poses_file.reset();
  const fusion::SelfReferencedOptions self_referenced = job.self_referenced;
  UseOdometryBeforeTheRobustLoss(&job.self_referenced);
  UseLinearTrackedImage(&job.self_referenced);
  job.self_referenced.surface.settled_plane_width_m =
      fusion::SurfaceModelOptions{}.settled_plane_width_m;
  const ReconstructReport settled = run("one_settled", 1);
  EXPECT_GT(settled.pose_details.value("points_placed_again_on_settled_plane", 0), 0);
  std::printf(
      "one pass with the odometry's options as written, the points placed again on the "
      "settled plane: %.2f mm\n",
      shaft_residual(settled) * 1e3);
  job.self_referenced = self_referenced;  // (settled_plane_width_m 0 again)

  // A first start far from settled (here by a tolerance tightened
  // twentyfold) runs again on half the image where the first pass is the
  // last, not where more passes follow: they start on the surface the first
  // measured over the whole scan, and the shaft needs the full image.
  job.poses_file.reset();
  job.self_referenced.init_settled_m = 0.0001;
  const ReconstructReport tight_one = run("tight_one", 1);
  EXPECT_EQ(tight_one.tracking_retried_from_width, 640);
  EXPECT_EQ(tight_one.pose_details.value("tracked_image_width", 0), 320);
  const ReconstructReport tight_auto = run("tight_auto", 0);
  EXPECT_GE(tight_auto.passes, 3);
  EXPECT_EQ(tight_auto.tracking_retried_from_width, 0);
  EXPECT_EQ(tight_auto.pose_details.value("tracked_image_width", 0), 640);
  fs::remove_all(root);
}

}  // namespace
}  // namespace uwscan
