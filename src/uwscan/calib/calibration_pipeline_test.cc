// The whole image path of `uwscan calibrate camera --model flatport --water`:
// boards rendered through a flat-port camera (in air and under water),
// written as PNGs, detected, calibrated. A stand-in for the simulator's
// `aquarium` scenario.
#include "uwscan/calib/calibration_pipeline.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <opencv2/imgcodecs.hpp>

#include "uwscan/calib/board_render.h"
#include "uwscan/calib/synthetic_views.h"
#include "uwscan/io/rig_yaml.h"
#include "uwscan/util/error.h"

namespace uwscan {
namespace {

namespace fs = std::filesystem;

// Renders `count` views at the given range band into `folder`.
void RenderViews(const Camera& camera, const BoardSpec& board, double min_range, double max_range,
                 int count, unsigned seed, const fs::path& folder) {
  SyntheticViewOptions views;
  views.num_views = count;
  views.min_range_m = min_range;
  views.max_range_m = max_range;
  views.max_tilt_deg = 25.0;  // SB's own refinement is biased beyond ~30 deg
  views.margin_px = 15.0;
  views.seed = seed;
  std::vector<Rigid3d> poses;
  SyntheticCornerSet(camera, board, views, &poses);
  fs::create_directories(folder);
  BoardRenderOptions render;
  render.blur_sigma_px = 0.6;
  render.noise_sigma = 2.0;
  for (size_t i = 0; i < poses.size(); ++i) {
    render.seed = seed * 100 + i;
    std::vector<Eigen::Vector2d> corners;
    const cv::Mat image = RenderBoardThroughCamera(camera, board, poses[i], render, &corners);
    char name[32];
    std::snprintf(name, sizeof(name), "%03zu.png", i);
    cv::imwrite((folder / name).string(), image);
  }
}

TEST(CalibrationPipeline, FlatPortFromRenderedAirAndWaterImages) {
  Camera truth;
  truth.name = "cam0";
  truth.width = 800;
  truth.height = 600;
  truth.model = CameraModelId::kFlatPort;
  truth.intrinsics = {700.0, 700.0, 401.0, 297.0};
  truth.distortion = {-0.05, 0.1, 0.0, 0.0, 0.0};
  const double tilt = 4.0 * M_PI / 180.0;
  truth.port.normal = Eigen::Vector3d(std::sin(tilt), 0.0, std::cos(tilt));
  truth.port.d_air = 0.010;
  truth.port.d_glass = 0.006;
  truth.port.n_glass = 1.52;
  truth.port.n_water = 1.333;
  Camera air_truth = truth;
  air_truth.port.n_water = 1.0;
  const BoardSpec board{9, 6, 0.03};
  const fs::path root = fs::temp_directory_path() / ("uwscan_pipeline_" + std::to_string(getpid()));
  RenderViews(air_truth, board, 0.35, 0.7, 12, 1, root / "air");
  RenderViews(truth, board, 0.3, 0.6, 12, 2, root / "water");

  CameraPipelineOptions options;
  options.images = root / "air";
  options.water = root / "water";
  options.board = board;
  options.model = CameraModelId::kFlatPort;
  options.n_glass = 1.52;
  options.d_glass = 0.006;
  options.n_water = 1.333;
  options.calibration.fix_k3 = true;
  const CameraPipelineResult out = RunCameraCalibration(options);
  // The two folders swapped, or the "water" views taken in air: a pinhole
  // fitted to them is 1 / 1.33 or 1 times as long in focal length as one
  // fitted in air, not about 1.33 times; the error says which.
  const auto error_of = [&](const fs::path& images, const fs::path& water) {
    CameraPipelineOptions wrong = options;
    wrong.images = images;
    wrong.water = water;
    try {
      RunCameraCalibration(wrong);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(
      error_of(root / "water", root / "air").find("are --images (in air) and --water swapped?"),
      std::string::npos);
  EXPECT_NE(
      error_of(root / "air", root / "air").find("were these views taken in air, not in water?"),
      std::string::npos);
  fs::remove_all(root);
  for (const std::string& line : out.log) std::printf("%s\n", line.c_str());
  const Camera& c = out.result.camera;
  const double tilt_error_deg =
      std::acos(std::min(1.0, c.port.normal.normalized().dot(truth.port.normal))) * 180 / M_PI;
  EXPECT_EQ(out.result.stage, "flatport-joint");
  // Issue 5 targets (measured: 0.05 mm, 0.003 deg, 0.021 px).
  EXPECT_NEAR(c.port.d_air, truth.port.d_air, 3e-4);
  EXPECT_LT(tilt_error_deg, 0.2);
  EXPECT_NEAR(c.intrinsics[0], truth.intrinsics[0], 0.2);
  EXPECT_LT(out.result.rms_px, 0.05);
  EXPECT_TRUE(out.report.contains("pinhole_vs_flatport"));
  // Standard deviations from the covariance: d_air's is positive and
  // consistent with the error.
  bool has_d_air = false;
  for (const auto& p : out.report["result"]["parameters"]) {
    if (p["name"] != "d_air") continue;
    has_d_air = true;
    ASSERT_TRUE(p["std"].is_number());
    const double std_dev = p["std"].get<double>();
    std::printf("d_air %.3f +- %.3f mm\n", p["value"].get<double>() * 1e3, std_dev * 1e3);
    EXPECT_GT(std_dev, 1e-6);
    EXPECT_LT(std::abs(c.port.d_air - truth.port.d_air), 5.0 * std_dev);
  }
  EXPECT_TRUE(has_d_air);
  // The calibrated flat-port camera is a valid rig camera and survives rig.yaml.
  Rig rig;
  rig.cameras.push_back(c);
  const Rig back = ParseRigYaml(RigToYaml(rig), "calibrated rig");
  EXPECT_EQ(back.cameras[0].port.d_air, c.port.d_air);
  EXPECT_TRUE(back.cameras[0].IsFlatPort());
  EXPECT_FALSE(out.residual_plot.empty());
}

}  // namespace
}  // namespace uwscan
