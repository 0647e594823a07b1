#include "uwscan/pipeline/track_accuracy_benchmark.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>

#include "uwscan/io/tum.h"
#include "uwscan/sim/simulate.h"
#include "uwscan/util/error.h"

namespace uwscan {
namespace {
namespace fs = std::filesystem;

// The poses' motion from the first pose exaggerated by `factor` (rotation
// angle and translation): a scene point's true image displacement grows
// by about that factor while the images stay as they are.
std::vector<StampedPose> Exaggerated(const std::vector<StampedPose>& poses, double factor) {
  std::vector<StampedPose> out = poses;
  const Rigid3d first_inverse = poses.front().world_from_camera.Inverse();
  for (StampedPose& pose : out) {
    const Rigid3d relative = first_inverse * pose.world_from_camera;
    const Eigen::AngleAxisd angle_axis(relative.rotation);
    const Rigid3d scaled(
        Eigen::Quaterniond(Eigen::AngleAxisd(factor * angle_axis.angle(), angle_axis.axis())),
        factor * relative.translation);
    pose.world_from_camera = poses.front().world_from_camera * scaled;
  }
  return out;
}

// On a simulated hull hover the tracks follow the truth to a fraction of a
// pixel, without a lag of more than 2 % of the motion; with the true motion
// exaggerated by 6 % the benchmark reports the tracks about 6 % short, so
// it does measure a lag.
TEST(TrackAccuracyBenchmark, TracksFollowTheTruthAndALagIsSeen) {
  const fs::path dir =
      fs::temp_directory_path() / ("uwscan_track_accuracy_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  sim::ScenarioOptions scenario;
  scenario.width = 320;
  scenario.height = 240;
  scenario.frames = 40;
  scenario.seed = 3;
  sim::SimulateScenario("hull", scenario, dir / "data");
  TrackAccuracyOptions options;
  options.dataset = dir / "data";
  const TrackAccuracyResult truth = RunTrackAccuracyBenchmark(options);
  std::printf("%s\n", truth.ToJson().dump().c_str());
  EXPECT_EQ(truth.frames, 40);
  EXPECT_GT(truth.samples, 1000);
  EXPECT_LT(truth.lost, truth.samples / 10);
  EXPECT_LT(truth.median_error_px, 0.6);  // drift over re-anchoring included
  // The gain along the axis the image moves most along.
  const bool along_y = truth.all.motion_y_px > truth.all.motion_x_px;
  const double gain = along_y ? truth.all.y : truth.all.x;
  EXPECT_GT(std::max(truth.all.motion_x_px, truth.all.motion_y_px), 5.0);
  EXPECT_LT(std::abs(gain), 0.02);

  WriteTum(dir / "data" / "groundtruth.tum",
           Exaggerated(ReadTum(dir / "data" / "groundtruth.tum"), 1.06));
  const TrackAccuracyResult exaggerated = RunTrackAccuracyBenchmark(options);
  const double lag = along_y ? exaggerated.all.y : exaggerated.all.x;
  std::printf("truth motion x 1.06: flow gain - 1 = %.2f %%\n", 100 * lag);
  EXPECT_LT(lag, 1.0 / 1.06 - 1.0 + 0.015);
  EXPECT_GT(lag, 1.0 / 1.06 - 1.0 - 0.015);

  fs::remove(dir / "data" / "scene.yaml");
  EXPECT_THROW(
      {
        try {
          RunTrackAccuracyBenchmark(options);
        } catch (const Error& e) {
          EXPECT_NE(std::string(e.what()).find("scene.yaml"), std::string::npos) << e.what();
          throw;
        }
      },
      Error);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace uwscan
