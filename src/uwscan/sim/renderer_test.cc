// Must-show checks of issue 3 on small in-memory renders: the laser line is
// where the models say, Beer–Lambert attenuation per channel, turbidity
// widens/dims the line and raises the background, determinism.
#include "uwscan/sim/renderer.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "uwscan/sim/scenario.h"
#include "uwscan/sim/testing.h"

namespace uwscan::sim {
namespace {

using testing::LookingDown;
using testing::PlaneConfig;
using testing::TruthAtRow;

// Centroid of the green channel across the line in one row, within +-3 px
// of the brightest pixel near `guess`.
double PeakInRow(const cv::Mat& electrons, int row, double guess) {
  int best = static_cast<int>(std::round(guess));
  for (int x = best - 3; x <= best + 3; ++x) {
    if (electrons.at<cv::Vec3f>(row, x)[1] > electrons.at<cv::Vec3f>(row, best)[1]) best = x;
  }
  double sum = 0, weighted = 0;
  for (int x = best - 3; x <= best + 3; ++x) {
    const double value = electrons.at<cv::Vec3f>(row, x)[1];
    sum += value;
    weighted += value * x;
  }
  return weighted / sum;
}

TEST(RendererTest, LaserTruthProjectsExactlyAndLiesOnSheetAndSurface) {
  const Renderer renderer(PlaneConfig(320, 240, "clear"));
  for (double angle : {0.1, -0.1, -0.3}) {
    FrameState state;
    state.world_from_camera = LookingDown(2.0);
    state.laser_angles_rad = {angle};
    const auto truth = renderer.LaserGroundTruth(state);
    ASSERT_GT(truth.size(), 200u) << "angle " << angle;
    const LineProjector& laser = renderer.config().rig.lasers[0];
    LineProjector turned = laser;
    turned.camera_from_laser = renderer.CameraFromLaser(0, angle);
    const Surface& plane = renderer.config().scene.surfaces[0];
    for (const LaserPoint& point : truth) {
      const auto pixel = renderer.camera().Project(point.point_in_camera, ProjectionMethod::kExact);
      ASSERT_TRUE(pixel.has_value());
      EXPECT_LT((*pixel - point.pixel).norm(), 0.01);
      EXPECT_NEAR(*turned.SheetResidual(point.point_in_camera), 0.0, 1e-12);
      const Eigen::Vector3d point_in_world = state.world_from_camera * point.point_in_camera;
      EXPECT_NEAR(plane.ImplicitResidual(plane.world_from_surface.Inverse() * point_in_world), 0.0,
                  1e-9);
    }
  }
}

double MaxPeakError(const SimConfig& config, double angle, double* mean_error) {
  const Renderer renderer(config);
  FrameState state;
  state.world_from_camera = LookingDown(2.0);
  state.laser_angles_rad = {angle};
  const RenderedFrame frame = renderer.Render(state);
  const auto truth = renderer.LaserGroundTruth(state, 0.5);
  const int width = config.rig.cameras[0].width, height = config.rig.cameras[0].height;
  double max_error = 0, sum_error = 0;
  int rows = 0;
  for (int row = 5; row < height - 5; ++row) {
    const auto u = TruthAtRow(truth, row);
    if (!u || *u < 8 || *u > width - 9) continue;
    const double error = PeakInRow(frame.electrons, row, *u) - *u;
    max_error = std::max(max_error, std::abs(error));
    sum_error += std::abs(error);
    ++rows;
  }
  EXPECT_GT(rows, height / 2);
  *mean_error = sum_error / std::max(rows, 1);
  return max_error;
}

TEST(RendererTest, ClearWaterLinePeakIsAtTheTruthWithinATenthOfAPixel) {
  // Default line (1/e^2 width 2 mm + 2 mrad, about 6 mm at 2 m) at 640x480:
  // sigma about 0.4 px, a resolved line.
  for (double angle : {0.05, -0.25}) {
    double mean = 0;
    EXPECT_LT(MaxPeakError(PlaneConfig(640, 480, "clear"), angle, &mean), 0.1) << angle;
    EXPECT_LT(mean, 0.03) << angle;
  }
  // At 320x240 the same line is a fifth of a pixel wide and no estimator can
  // place it better than pixel locking allows (> 0.1 px); the thesis's 8 mm
  // line (§5.3) is resolved again.
  SimConfig coarse = PlaneConfig(320, 240, "clear");
  double mean = 0;
  EXPECT_GT(MaxPeakError(coarse, 0.05, &mean), 0.1);
  coarse.lasers[0].width_m = 0.008;
  EXPECT_LT(MaxPeakError(coarse, 0.05, &mean), 0.1);
  EXPECT_LT(mean, 0.03);
}

TEST(RendererTest, AttenuationFollowsBeerLambertPerChannelAndRedFadesFirst) {
  // Uniform daylight on a target facing the camera: the radiance leaving the
  // target does not depend on range, so the camera-path transmission is the
  // only change: e(r2) / e(r1) = exp(-c (r2 - r1)) per channel.
  const std::vector<double> ranges = {1.0, 2.0, 3.0, 4.0};
  std::vector<Eigen::Vector3d> signal;
  for (double range : ranges) {
    SimConfig config = PlaneConfig(64, 48, "clear", 0.0);
    config.lasers.clear();
    config.ambient.irradiance_rgb = {1.0, 1.0, 1.0};
    config.render.forward_scatter = false;
    config.render.backscatter = false;
    FrameState state;
    state.world_from_camera = LookingDown(range);
    const RenderedFrame frame = Renderer(config).Render(state);
    const cv::Vec3f e = frame.electrons.at<cv::Vec3f>(24, 32);
    const double path = frame.range_m.at<float>(24, 32);
    EXPECT_NEAR(path, range - 0.017 /* d_air + d_glass */, 0.005);
    signal.push_back(Eigen::Vector3d(e[0], e[1], e[2]));
  }
  const Eigen::Vector3d c = Medium::Preset("clear").AttenuationRgb();
  for (size_t i = 1; i < ranges.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      const double measured = std::log(signal[0][k] / signal[i][k]) / (ranges[i] - ranges[0]);
      EXPECT_NEAR(measured, c[k], 1e-4 * c[k] + 1e-6) << "channel " << k << " range " << ranges[i];
    }
  }
  // Red has the largest attenuation in clear water and loses most.
  const Eigen::Vector3d kept = signal.back().cwiseQuotient(signal.front());
  EXPECT_LT(kept[0], kept[1]);
  EXPECT_LT(kept[0], kept[2]);
}

struct LineStats {
  double peak = 0, background = 0, width_px = 0;
};

// Mean over rows of the green profile across the line: background far from
// the line, peak above background, and full width at half maximum.
LineStats MeasureLine(const std::string& water) {
  const Renderer renderer(PlaneConfig(320, 240, water));
  FrameState state;
  state.world_from_camera = LookingDown(2.0);
  state.laser_angles_rad = {-0.1};
  const RenderedFrame frame = renderer.Render(state);
  const auto truth = renderer.LaserGroundTruth(state, 0.5);
  LineStats stats;
  int rows = 0;
  for (int row = 60; row < 180; row += 4) {
    const auto u = TruthAtRow(truth, row);
    if (!u) continue;
    const int centre = static_cast<int>(std::round(*u));
    auto green = [&](int x) { return frame.electrons.at<cv::Vec3f>(row, x)[1]; };
    const double background = 0.5 * (green(centre - 60) + green(centre + 60));
    double peak = 0;
    for (int x = centre - 2; x <= centre + 2; ++x)
      peak = std::max<double>(peak, green(x) - background);
    int above = 0;
    for (int x = centre - 50; x <= centre + 50; ++x) above += (green(x) - background) >= 0.5 * peak;
    stats.peak += peak;
    stats.background += background;
    stats.width_px += above;
    ++rows;
  }
  EXPECT_GT(rows, 20);
  stats.peak /= rows;
  stats.background /= rows;
  stats.width_px /= rows;
  return stats;
}

TEST(RendererTest, TurbidityWidensAndDimsTheLineAndRaisesTheBackground) {
  const LineStats clear = MeasureLine("clear");
  const LineStats coastal = MeasureLine("coastal");
  const LineStats turbid = MeasureLine("turbid");
  EXPECT_LE(clear.width_px, 2.0);  // the core: about one pixel at 2 m, 320 px
  EXPECT_GT(turbid.width_px, 3 * clear.width_px);
  EXPECT_GE(coastal.width_px, clear.width_px);
  EXPECT_LT(coastal.peak, 0.7 * clear.peak);
  EXPECT_LT(turbid.peak, 0.05 * coastal.peak);
  // Scattered laser light raises the background against the line.
  EXPECT_GT(coastal.background, 2 * clear.background);
  EXPECT_GT(coastal.background / coastal.peak, 10 * clear.background / clear.peak);
  EXPECT_GT(turbid.background / turbid.peak, 10 * coastal.background / coastal.peak);
}

TEST(RendererTest, DeterministicForASeedAndIndependentOfThreads) {
  ScenarioOptions options;
  options.width = 160;
  options.height = 120;
  options.frames = 3;
  Scenario scenario = MakeScenario("tank-target", options);
  const Trajectory trajectory(scenario.motion);
  const FrameState state = scenario.FrameAt(trajectory, 2);
  const cv::Mat a = Renderer(scenario.config).Render(state).image;
  scenario.config.render.threads = 1;
  const cv::Mat b = Renderer(scenario.config).Render(state).image;
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
  scenario.config.render.threads = 3;  // rows taken by whichever thread is free
  const cv::Mat c = Renderer(scenario.config).Render(state).image;
  EXPECT_EQ(cv::norm(a, c, cv::NORM_INF), 0.0);
  FrameState other = state;
  other.noise_seed += 1;
  EXPECT_GT(cv::norm(a, Renderer(scenario.config).Render(other).image, cv::NORM_L1), 0.0);
}

}  // namespace
}  // namespace uwscan::sim
