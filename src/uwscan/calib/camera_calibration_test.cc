#include "uwscan/calib/camera_calibration.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <random>

#include "uwscan/calib/board_pose.h"
#include "uwscan/calib/synthetic_views.h"
#include "uwscan/sim/scenario.h"
#include "uwscan/util/error.h"

namespace uwscan {
namespace {

const BoardSpec kBoard{11, 8, 0.025};

struct AquariumRun {
  CameraCalibrationResult air, water, joint;
};

AquariumRun RunAquarium(const Camera& truth, double noise_px, unsigned seed,
                        FlatPortResidualType residual = FlatPortResidualType::kExact) {
  Camera in_air_truth = truth;
  in_air_truth.port.n_water = 1.0;
  SyntheticViewOptions air_views;
  air_views.num_views = 24;
  air_views.min_range_m = 0.35;
  air_views.max_range_m = 0.8;
  air_views.noise_px = noise_px;
  air_views.seed = seed;
  const CornerSet air = SyntheticCornerSet(in_air_truth, kBoard, air_views);
  SyntheticViewOptions water_views = air_views;
  water_views.min_range_m = 0.25;
  water_views.max_range_m = 0.6;
  water_views.seed = seed + 100;
  const CornerSet water = SyntheticCornerSet(truth, kBoard, water_views);

  CameraCalibrationOptions options;
  options.fix_k3 = true;
  options.compute_covariance = false;  // see CovarianceGivesPlausibleStdDevs
  AquariumRun run;
  const CameraCalibrationResult pinhole = CalibratePinhole(air, truth, options);
  FlatPortAirOptions air_options;
  air_options.common = options;
  air_options.d_glass = truth.port.d_glass;
  air_options.n_glass = truth.port.n_glass;
  run.air = CalibrateFlatPortInAir(air, pinhole, air_options);
  WaterRefinementOptions water_options;
  water_options.common = options;
  water_options.n_water = truth.port.n_water;
  water_options.residual = residual;
  run.water = RefineFlatPortInWater(water, run.air.camera, water_options);
  run.joint = CalibrateFlatPortJoint(air, run.air, water, water_options);
  return run;
}

double TiltErrorDeg(const Camera& truth, const Camera& c) {
  return std::acos(std::min(1.0, c.port.normal.normalized().dot(truth.port.normal.normalized()))) *
         180.0 / M_PI;
}

void Print(const char* what, const Camera& truth, const CameraCalibrationResult& r) {
  const Camera& c = r.camera;
  std::printf(
      "%-8s d_air %5.2f -> %8.4f mm  tilt %.1f -> %7.4f deg (err %.4f)  rms %.4f px  "
      "fx %.3f  k1 %.5f  k2 %.5f\n",
      what, truth.port.d_air * 1e3, c.port.d_air * 1e3, truth.port.TiltRad() * 180 / M_PI,
      c.port.TiltRad() * 180 / M_PI, TiltErrorDeg(truth, c), r.rms_px, c.intrinsics[0],
      c.distortion[0], c.distortion[1]);
}

// Joint (air + water views) flat-port calibration: port within the stated
// tolerances, RMS at the injected noise level.
void ExpectAquariumRecovered(const Camera& truth, const AquariumRun& run, double noise_px,
                             double d_air_tol_m, double tilt_tol_deg) {
  Print("air", truth, run.air);
  Print("water", truth, run.water);
  Print("joint", truth, run.joint);
  const Camera& c = run.joint.camera;
  EXPECT_NEAR(c.port.d_air, truth.port.d_air, d_air_tol_m);
  EXPECT_LT(TiltErrorDeg(truth, c), tilt_tol_deg);
  // 2D RMS of N(0, s^2) noise per axis is sqrt(2) s (minus the fitted dof).
  const double expected_rms = std::sqrt(2.0) * noise_px;
  EXPECT_NEAR(run.joint.rms_px, expected_rms, 0.05 * expected_rms + 1e-5);
  // The sequential stages hold the normal at [0, 0, 1] in air (Tab. 4.10);
  // for the 4 deg port that leaves ~0.003 px (cf. Fig. 4.22).
  for (const auto* r : {&run.air, &run.water}) {
    EXPECT_NEAR(r->rms_px, expected_rms, 0.05 * expected_rms + 0.005) << r->stage;
  }
  EXPECT_EQ(run.joint.used_views, 48);
  // Sequential refinement (Tab. 4.11): focal length held, distortion free;
  // the model says it does not change under water, and it stays put.
  const Camera& w = run.water.camera;
  EXPECT_EQ(w.intrinsics, run.air.camera.intrinsics);
  EXPECT_NEAR(w.distortion[0], run.air.camera.distortion[0], 0.005);
  EXPECT_NEAR(w.distortion[1], run.air.camera.distortion[1], 0.005);
  EXPECT_EQ(run.water.used_views, 24);
}

TEST(AquariumCalibration, NoiseFreeRecoversPortExactly) {
  for (double d_air : {0.001, 0.010, 0.020}) {
    const Camera truth = AquariumTestCamera(d_air, d_air == 0.020 ? 4.0 : 0.0);
    const AquariumRun run = RunAquarium(truth, 0.0, 7);
    ExpectAquariumRecovered(truth, run, 0.0, 1e-6, 1e-4);
    EXPECT_NEAR(run.joint.camera.intrinsics[0], truth.intrinsics[0], 1e-3);
    EXPECT_NEAR(run.joint.camera.distortion[0], truth.distortion[0], 1e-6);
  }
}

TEST(AquariumCalibration, WithCornerNoiseWithinThesisTolerances) {
  // The thesis's set-ups (Tab. 6.2): 1, 10, 20 mm orthogonal and 20 mm at 4 deg.
  const std::pair<double, double> setups[] = {
      {0.001, 0.0}, {0.010, 0.0}, {0.020, 0.0}, {0.020, 4.0}};
  for (const auto& [d_air, tilt] : setups) {
    const Camera truth = AquariumTestCamera(d_air, tilt);
    const AquariumRun run = RunAquarium(truth, 0.1, 11);
    ExpectAquariumRecovered(truth, run, 0.1, 3e-4, 0.2);
  }
}

}  // namespace
}  // namespace uwscan

namespace uwscan {
namespace {

TEST(CameraCalibration, OutlierLoopDropsCorruptedViewWithReason) {
  const Camera truth = AquariumTestCamera(0.010, 0.0);
  Camera air_truth = truth;
  air_truth.port.n_water = 1.0;
  SyntheticViewOptions views;
  views.num_views = 10;
  views.min_range_m = 0.35;
  views.max_range_m = 0.8;
  views.noise_px = 0.1;
  CornerSet set = SyntheticCornerSet(air_truth, kBoard, views);
  // View 3: a detector glitch moves its corners by up to 3 px.
  for (size_t i = 0; i < set.views[3].corners.size(); ++i) {
    set.views[3].corners[i] += Eigen::Vector2d(3.0 * std::sin(0.7 * i), 3.0 * std::cos(1.3 * i));
  }
  CameraCalibrationOptions options;
  options.fix_k3 = true;
  const CameraCalibrationResult result = CalibratePinhole(set, truth, options);
  EXPECT_EQ(result.used_views, 9);
  EXPECT_FALSE(result.views[3].used);
  EXPECT_NE(result.views[3].dropped_reason.find("above threshold"), std::string::npos)
      << result.views[3].dropped_reason;
  EXPECT_EQ(result.outlier_rounds, 1);
  EXPECT_NEAR(result.rms_px, std::sqrt(2.0) * 0.1, 0.01);
  // Covariance: fx standard deviation positive and the error within 4 sigma.
  const auto fx = std::find_if(result.parameters.begin(), result.parameters.end(),
                               [](const ParameterEstimate& p) { return p.name == "fx"; });
  ASSERT_NE(fx, result.parameters.end());
  EXPECT_GT(fx->std_dev, 0.01);
  EXPECT_LT(std::abs(fx->value - truth.intrinsics[0]), 4.0 * fx->std_dev);
}

TEST(CameraCalibration, TooFewViewsIsAnError) {
  SyntheticViewOptions views;
  views.num_views = 2;
  const CornerSet set = SyntheticCornerSet(AquariumTestCamera(0.01, 0.0), kBoard, views);
  EXPECT_THROW(CalibratePinhole(set, Camera(), CameraCalibrationOptions()), Error);
}

// The thesis's residual (Taylor centred at the measured corner, §4.4) and
// the exact one give the same port; the water index can be estimated.
TEST(CameraCalibration, TaylorResidualAndWaterIndexEstimation) {
  const Camera truth = AquariumTestCamera(0.020, 4.0);
  Camera air_truth = truth;
  air_truth.port.n_water = 1.0;
  SyntheticViewOptions views;
  views.num_views = 16;
  views.min_range_m = 0.35;
  views.max_range_m = 0.8;
  const CornerSet air = SyntheticCornerSet(air_truth, kBoard, views);
  views.min_range_m = 0.25;
  views.max_range_m = 0.6;
  views.seed = 5;
  const CornerSet water = SyntheticCornerSet(truth, kBoard, views);
  CameraCalibrationOptions options;
  options.fix_k3 = true;
  const auto pinhole = CalibratePinhole(air, truth, options);
  FlatPortAirOptions air_options;
  air_options.common = options;
  air_options.d_glass = 0.006;
  air_options.n_glass = 1.52;
  const auto in_air = CalibrateFlatPortInAir(air, pinhole, air_options);
  WaterRefinementOptions water_options;
  water_options.common = options;
  water_options.n_water = 1.333;
  water_options.residual = FlatPortResidualType::kTaylor;
  water_options.taylor_iterations = 1;
  const auto taylor = CalibrateFlatPortJoint(air, in_air, water, water_options);
  EXPECT_NEAR(taylor.camera.port.d_air, 0.020, 1e-5);
  EXPECT_LT(TiltErrorDeg(truth, taylor.camera), 1e-3);
  EXPECT_LT(taylor.rms_px, 1e-4);

  water_options.residual = FlatPortResidualType::kExact;
  water_options.n_water = 1.30;  // wrong start, estimated
  water_options.estimate_n_water = true;
  const auto estimated = CalibrateFlatPortJoint(air, in_air, water, water_options);
  std::printf("n_water estimated %.5f (truth 1.333), d_air %.3f mm\n",
              estimated.camera.port.n_water, estimated.camera.port.d_air * 1e3);
  EXPECT_NEAR(estimated.camera.port.n_water, 1.333, 1e-4);
  EXPECT_NEAR(estimated.camera.port.d_air, 0.020, 1e-4);
  const bool reported = std::any_of(estimated.parameters.begin(), estimated.parameters.end(),
                                    [](const ParameterEstimate& p) { return p.name == "n_water"; });
  EXPECT_TRUE(reported);
}

}  // namespace
}  // namespace uwscan

namespace uwscan {
namespace {

// The simulator's `aquarium` scenario (§6.1) at the corner level: its views
// (10 in air without the window, 10 in water, 0.25-0.6 m) and cameras, the
// corners projected exactly (+ optional noise). Calibrated as `uwscan
// calibrate camera --air-without-port` does: pinhole in air, sequential
// refinement in water, then the joint fit with the air views as straight-ray
// views.
struct ScenarioRun {
  Camera truth;
  CameraCalibrationResult pinhole, sequential, joint;
};

ScenarioRun RunAquariumScenario(double gap_mm, double tilt_deg, double noise_px, uint64_t seed,
                                int views = 10) {
  sim::ScenarioOptions options;
  options.frames = views;
  options.seed = seed;
  options.port_gap_mm = gap_mm;
  options.port_tilt_deg = tilt_deg;
  const sim::Scenario scenario = sim::MakeScenario("aquarium", options);
  const BoardSpec board{8, 6, 0.025};
  // Any board frame in the board plane; centred like the simulator's squares.
  const Eigen::Vector3d offset(-3.5 * board.square_m, -2.5 * board.square_m, 0.0);
  std::mt19937 rng(static_cast<unsigned>(seed));
  std::normal_distribution<double> noise(0.0, noise_px);
  std::map<std::string, CornerSet> sets;
  ScenarioRun run;
  for (const sim::CalibrationSet& set : scenario.calibration) {
    const Camera& camera = set.config.rig.cameras.at(0);
    if (set.name == "water") run.truth = camera;
    CornerSet& corners = sets[set.name];
    corners.board = board;
    corners.width = camera.width;
    corners.height = camera.height;
    for (size_t v = 0; v < set.views.size(); ++v) {
      const Rigid3d camera_from_world = set.views[v].world_from_camera.Inverse();
      ViewCorners view{set.name + std::to_string(v), {}};
      for (const Eigen::Vector3d& point : board.Corners()) {
        const auto pixel = camera.Project(camera_from_world * (point + offset), ProjectionMethod::kExact);
        EXPECT_TRUE(pixel.has_value());
        view.corners.push_back(*pixel + Eigen::Vector2d(noise(rng), noise(rng)));
      }
      corners.views.push_back(view);
    }
  }
  CameraCalibrationOptions calibration;
  calibration.fix_k3 = true;
  Camera start = run.truth;
  start.intrinsics = {1000.0, 1000.0, 640.0, 480.0};
  start.distortion = {};
  run.pinhole = CalibratePinhole(sets.at("air"), start, calibration);
  Camera flat = run.pinhole.camera;
  flat.model = CameraModelId::kFlatPort;
  flat.port = run.truth.port;
  flat.port.normal = Eigen::Vector3d::UnitZ();
  flat.port.d_air = 0.01;  // the pipeline's start
  WaterRefinementOptions water;
  water.common = calibration;
  water.n_water = run.truth.port.n_water;
  run.sequential = RefineFlatPortInWater(sets.at("water"), flat, water);
  run.joint = CalibrateFlatPortJointPortlessAir(sets.at("air"), run.pinhole, sets.at("water"),
                                                run.sequential.camera, water);
  return run;
}

double StdOf(const CameraCalibrationResult& r, const std::string& name) {
  for (const ParameterEstimate& p : r.parameters)
    if (p.name == name) return p.std_dev;
  return std::numeric_limits<double>::quiet_NaN();
}

TEST(AquariumScenarioCalibration, NoiseFreeRecoversGapAndTilt) {
  for (const auto& [gap_mm, tilt_deg] : {std::pair{1.0, 0.0}, {10.0, 0.0}, {20.0, 0.0}, {20.0, 4.0}}) {
    const ScenarioRun run = RunAquariumScenario(gap_mm, tilt_deg, 0.0, 31);
    Print("joint", run.truth, run.joint);
    EXPECT_NEAR(run.joint.camera.port.d_air, run.truth.port.d_air, 3e-4);
    EXPECT_LT(TiltErrorDeg(run.truth, run.joint.camera), 0.2);
    EXPECT_LT(run.joint.rms_px, 0.01);
    EXPECT_EQ(run.joint.used_views, 20);
  }
}

// With 0.1 px corner noise the ten views of §6.1 do not pin d_air to 0.3 mm:
// the covariance gives ~1-2 mm (the thesis reports relative changes "better
// than 1 mm"). The estimate must agree with the truth within 3 sigma, the
// tilt within 0.2 deg, and the RMS sit at the noise level.
TEST(AquariumScenarioCalibration, CornerNoiseWithinCovariance) {
  for (const auto& [gap_mm, tilt_deg] : {std::pair{1.0, 0.0}, {20.0, 4.0}}) {
    const ScenarioRun run = RunAquariumScenario(gap_mm, tilt_deg, 0.1, 37);
    Print("joint", run.truth, run.joint);
    const double sigma = StdOf(run.joint, "d_air");
    std::printf("  d_air sigma %.2f mm\n", sigma * 1e3);
    ASSERT_TRUE(std::isfinite(sigma));
    EXPECT_LT(sigma, 3e-3);
    EXPECT_NEAR(run.joint.camera.port.d_air, run.truth.port.d_air, 3.0 * sigma);
    EXPECT_LT(TiltErrorDeg(run.truth, run.joint.camera), 0.2);
    EXPECT_NEAR(run.joint.rms_px, std::sqrt(2.0) * 0.1, 0.015);
    // Focal length and distortion shared with the air views stay at truth.
    EXPECT_NEAR(run.joint.camera.intrinsics[0], run.truth.intrinsics[0], 1.5);
    EXPECT_NEAR(run.joint.camera.distortion[0], run.truth.distortion[0], 0.005);
  }
}

// Precision of d_air over seeds (for docs/BENCHMARKS.md; not run by CTest):
//   build/tests/calib_camera_calibration_test --gtest_also_run_disabled_tests
//     --gtest_filter='*DISABLED_GapPrecisionOverSeeds'
TEST(AquariumScenarioCalibration, DISABLED_GapPrecisionOverSeeds) {
  for (int views : {10, 20, 40}) {
    for (double gap_mm : {1.0, 10.0, 20.0}) {
      double sum_sq_joint = 0, sum_sq_seq = 0, sum_sigma = 0, sum_sq_tilt = 0;
      const int runs = 20;
      for (int seed = 100; seed < 100 + runs; ++seed) {
        const ScenarioRun run = RunAquariumScenario(gap_mm, 4.0, 0.1, seed, views);
        sum_sq_joint += std::pow(run.joint.camera.port.d_air - run.truth.port.d_air, 2);
        sum_sq_seq += std::pow(run.sequential.camera.port.d_air - run.truth.port.d_air, 2);
        sum_sigma += StdOf(run.joint, "d_air");
        sum_sq_tilt += std::pow(TiltErrorDeg(run.truth, run.joint.camera), 2);
      }
      std::printf("| %d | %.0f | %.2f | %.2f | %.2f | %.3f |\n", views, gap_mm,
                  std::sqrt(sum_sq_joint / runs) * 1e3, sum_sigma / runs * 1e3,
                  std::sqrt(sum_sq_seq / runs) * 1e3, std::sqrt(sum_sq_tilt / runs));
    }
  }
}

}  // namespace
}  // namespace uwscan
