// A simulated dataset on disk reproduces its own geometry: laser_gt.csv,
// groundtruth.tum, frames.csv, rig.yaml and scene.yaml agree with each other
// and with the rendered pixels, and re-rendering from the files is exact.
#include "uwscan/sim/simulate.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <opencv2/imgproc.hpp>

#include "uwscan/io/dataset.h"
#include "uwscan/io/image.h"
#include "uwscan/io/rig_yaml.h"
#include "uwscan/io/tum.h"
#include "uwscan/sim/scene_yaml.h"
#include "uwscan/util/error.h"

namespace uwscan::sim {
namespace {

namespace fs = std::filesystem;

class SimulateTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("uwscan_simulate_test_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    ScenarioOptions options;
    options.width = 640;
    options.height = 480;
    options.frames = 3;
    options.output = OutputFormat::kRgb;
    result_ = SimulateScenario("tank-target", options, dir_ / "tank");
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }

  static fs::path dir_;
  static SimulateResult result_;
};

fs::path SimulateTest::dir_;
SimulateResult SimulateTest::result_;

TEST_F(SimulateTest, WritesTheDatasetFolder) {
  const fs::path tank = dir_ / "tank";
  for (const char* name : {"rig.yaml", "scene.yaml", "frames.csv", "groundtruth.tum",
                           "laser_gt.csv", "frames/000000.png", "frames/000002.png"}) {
    EXPECT_TRUE(fs::exists(tank / name)) << name;
  }
  EXPECT_EQ(result_.frames, 3);
  EXPECT_GT(result_.laser_points, 3 * 300);
  // Nothing left beside it (the temporary folder was renamed).
  int entries = 0;
  for (const auto& entry : fs::directory_iterator(dir_)) entries += entry.is_directory();
  EXPECT_EQ(entries, 1);
}

TEST_F(SimulateTest, LaserTruthAgreesWithPosesSceneAndRig) {
  const fs::path tank = dir_ / "tank";
  const Rig rig = ReadRigYaml(tank / "rig.yaml");
  const Scenario scenario = LoadDatasetScenario(tank);
  const auto poses = ReadTum(tank / "groundtruth.tum");
  const auto frames = ReadFramesCsv(tank / "frames.csv");
  const auto truth = ReadLaserTruthCsv(tank / "laser_gt.csv");
  ASSERT_EQ(poses.size(), 3u);
  ASSERT_EQ(frames.size(), 3u);
  const LaserSource& source = scenario.config.lasers[0];
  for (const LaserTruthRow& row : truth) {
    const Eigen::Vector3d point(row.x, row.y, row.z);
    const auto pixel = rig.cameras[0].Project(point, ProjectionMethod::kExact);
    ASSERT_TRUE(pixel);
    EXPECT_LT((*pixel - Eigen::Vector2d(row.u, row.v)).norm(), 0.01);
    // On the light sheet turned by the servo angle of frames.csv.
    LineProjector laser = rig.lasers[0];
    laser.camera_from_laser =
        laser.camera_from_laser * source.ServoRotation(*frames[row.frame].laser_angle_rad);
    EXPECT_NEAR(*laser.SheetResidual(point), 0.0, 1e-9);
    // On a surface of scene.yaml, placed in the world by groundtruth.tum.
    const Eigen::Vector3d world = poses[row.frame].world_from_camera * point;
    double residual = 1e9;
    for (const Surface& surface : scenario.config.scene.surfaces) {
      residual = std::min(
          residual,
          std::abs(surface.ImplicitResidual(surface.world_from_surface.Inverse() * world)));
    }
    EXPECT_LT(residual, 1e-8);
  }
}

TEST_F(SimulateTest, CheckerboardCornersAppearWherePosesAndSceneProjectThem) {
  const fs::path tank = dir_ / "tank";
  const Rig rig = ReadRigYaml(tank / "rig.yaml");
  const Scenario scenario = LoadDatasetScenario(tank);
  const auto poses = ReadTum(tank / "groundtruth.tum");
  const auto truth = ReadLaserTruthCsv(tank / "laser_gt.csv");
  const Surface* board = nullptr;
  for (const Surface& surface : scenario.config.scene.surfaces) {
    if (surface.texture.type == TextureType::kCheckerboard) board = &surface;
  }
  ASSERT_NE(board, nullptr);
  std::vector<double> errors;
  for (int frame = 0; frame < 3; ++frame) {
    cv::Mat image = ReadImage(tank / FrameFileName(frame)), red;
    cv::extractChannel(image, red, 2);  // red LED light
    const Rigid3d camera_from_world = poses[frame].world_from_camera.Inverse();
    std::vector<cv::Point2f> corners, projected;
    const Texture& t = board->texture;
    for (int j = 1; j < t.squares_y; ++j) {
      for (int i = 1; i < t.squares_x; ++i) {
        const Eigen::Vector3d local((i - 0.5 * t.squares_x) * t.scale_m,
                                    (j - 0.5 * t.squares_y) * t.scale_m, 0);
        const auto pixel =
            rig.cameras[0].Project(camera_from_world * (board->world_from_surface * local));
        ASSERT_TRUE(pixel);
        bool near_laser = false;
        for (const auto& row : truth) {
          near_laser |=
              row.frame == frame && std::hypot(row.u - pixel->x(), row.v - pixel->y()) < 8;
        }
        if (near_laser) continue;
        projected.emplace_back(pixel->x(), pixel->y());
      }
    }
    ASSERT_GT(projected.size(), 80u);
    corners = projected;
    cv::cornerSubPix(red, corners, cv::Size(3, 3), cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 1e-4));
    for (size_t k = 0; k < corners.size(); ++k)
      errors.push_back(cv::norm(corners[k] - projected[k]));
  }
  std::sort(errors.begin(), errors.end());
  std::cout << "corner error vs projected truth: median " << errors[errors.size() / 2]
            << " px, 95% " << errors[errors.size() * 95 / 100] << " px over " << errors.size()
            << " corners\n";
  EXPECT_LT(errors[errors.size() / 2], 0.15);  // median
  EXPECT_LT(errors[errors.size() * 95 / 100], 0.3);
}

TEST_F(SimulateTest, RerenderingFromTheFilesReproducesTheFramesExactly) {
  const fs::path tank = dir_ / "tank";
  const Scenario scenario = LoadDatasetScenario(tank);
  const auto poses = ReadTum(tank / "groundtruth.tum");
  const Renderer renderer(scenario.config);
  const Trajectory trajectory(scenario.motion);
  const FrameState state = scenario.FrameAt(trajectory, 1);
  EXPECT_LT((state.world_from_camera.translation - poses[1].world_from_camera.translation).norm(),
            1e-12);
  const cv::Mat again = renderer.Render(state).image;
  EXPECT_EQ(cv::norm(again, ReadImage(tank / FrameFileName(1)), cv::NORM_INF), 0.0);
}

TEST_F(SimulateTest, RefusesANonEmptyOutputFolderAndLeavesNothingBehind) {
  ScenarioOptions options;
  options.width = 32;
  options.height = 24;
  options.frames = 1;
  EXPECT_THROW(SimulateScenario("tank-target", options, dir_ / "tank"), Error);
  EXPECT_THROW(SimulateScenario("no-such-scenario", options, dir_ / "x"), UsageError);
  EXPECT_FALSE(fs::exists(dir_ / "x"));
  options.frames = 0;
  EXPECT_THROW(SimulateScenario("tank-target", options, dir_ / "y"), Error);
  EXPECT_FALSE(fs::exists(dir_ / "y"));
  int entries = 0;
  for (const auto& entry : fs::directory_iterator(dir_)) entries += entry.is_directory();
  EXPECT_EQ(entries, 1);
}

}  // namespace
}  // namespace uwscan::sim
