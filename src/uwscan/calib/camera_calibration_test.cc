#include "uwscan/calib/camera_calibration.h"

#include <gtest/gtest.h>

#include <cstdio>

#include "uwscan/calib/board_pose.h"
#include "uwscan/calib/synthetic_views.h"
#include "uwscan/util/error.h"

namespace uwscan {
namespace {

// Thesis §6.1 aquarium: camera (Pin-Air-like intrinsics) behind a 6 mm
// window (n_glass 1.52), fresh water 1.333.
Camera AquariumCamera(double d_air_m, double tilt_deg) {
  Camera camera;
  camera.name = "cam0";
  camera.width = 1280;
  camera.height = 960;
  camera.model = CameraModelId::kFlatPort;
  camera.intrinsics = {1112.70, 1112.58, 625.64, 443.93};
  camera.distortion = {-0.0489, 0.1037, 0.0005, -0.0003, 0.0};
  const double tilt = tilt_deg * M_PI / 180.0;
  camera.port.normal = Eigen::Vector3d(std::sin(tilt), 0.0, std::cos(tilt));
  camera.port.d_air = d_air_m;
  camera.port.d_glass = 0.006;
  camera.port.n_air = 1.0;
  camera.port.n_glass = 1.52;
  camera.port.n_water = 1.333;
  return camera;
}

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
    const Camera truth = AquariumCamera(d_air, d_air == 0.020 ? 4.0 : 0.0);
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
    const Camera truth = AquariumCamera(d_air, tilt);
    const AquariumRun run = RunAquarium(truth, 0.1, 11);
    ExpectAquariumRecovered(truth, run, 0.1, 3e-4, 0.2);
  }
}

}  // namespace
}  // namespace uwscan

namespace uwscan {
namespace {

TEST(CameraCalibration, OutlierLoopDropsCorruptedViewWithReason) {
  const Camera truth = AquariumCamera(0.010, 0.0);
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
  const CornerSet set = SyntheticCornerSet(AquariumCamera(0.01, 0.0), kBoard, views);
  EXPECT_THROW(CalibratePinhole(set, Camera(), CameraCalibrationOptions()), Error);
}

// The thesis's residual (Taylor centred at the measured corner, §4.4) and
// the exact one give the same port; the water index can be estimated.
TEST(CameraCalibration, TaylorResidualAndWaterIndexEstimation) {
  const Camera truth = AquariumCamera(0.020, 4.0);
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
