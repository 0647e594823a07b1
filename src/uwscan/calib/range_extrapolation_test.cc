// Issue 5 must-show: a flat-port calibration predicts corners at a range not
// used for calibration better than a pinhole calibrated under water.
#include <gtest/gtest.h>

#include <cstdio>

#include "uwscan/calib/board_pose.h"
#include "uwscan/calib/camera_calibration.h"
#include "uwscan/calib/synthetic_views.h"

namespace uwscan {
namespace {

// Mean over boards of the pose-fitted re-projection RMS: how well a model
// explains corners at that range, whatever pose it needs.
double FittedRms(const Camera& model, const CornerSet& check) {
  double sum = 0.0;
  for (const ViewCorners& view : check.views) {
    const auto pose = EstimateBoardPose(model, check.board, view.corners);
    EXPECT_TRUE(pose.has_value());
    sum += pose ? pose->rms_px : 1e9;
  }
  return sum / check.views.size();
}

TEST(RangeExtrapolation, FlatPortBeatsUnderwaterPinholeAtThreeMetres) {
  for (double tilt : {0.0, 4.0}) {
    const Camera truth = AquariumTestCamera(0.020, tilt);
    Camera air_truth = truth;
    air_truth.port.n_water = 1.0;
    SyntheticViewOptions air_views;
    air_views.num_views = 24;
    air_views.min_range_m = 0.5;
    air_views.max_range_m = 1.0;
    air_views.noise_px = 0.1;
    air_views.seed = 21;
    const CornerSet air = SyntheticCornerSet(air_truth, BoardSpec{9, 6, 0.045}, air_views);
    SyntheticViewOptions water_views = air_views;
    water_views.min_range_m = 0.6;  // calibrated at 0.5-1.5 m (board centre 0.6-1.5 m)
    water_views.max_range_m = 1.5;
    water_views.seed = 22;
    const CornerSet water = SyntheticCornerSet(truth, BoardSpec{9, 6, 0.045}, water_views);
    // The check set: a 1.6 m board at 3 m, noise-free, never used to calibrate.
    SyntheticViewOptions check_views;
    check_views.num_views = 5;
    check_views.min_range_m = 3.0;
    check_views.max_range_m = 3.0;
    check_views.max_tilt_deg = 20.0;
    check_views.seed = 23;
    const CornerSet check = SyntheticCornerSet(truth, BoardSpec{17, 12, 0.1}, check_views);
    SyntheticViewOptions near_views = check_views;
    near_views.min_range_m = near_views.max_range_m = 1.0;
    const CornerSet near = SyntheticCornerSet(truth, BoardSpec{9, 6, 0.045}, near_views);

    CameraCalibrationOptions options;
    options.fix_k3 = true;
    options.compute_covariance = false;
    const auto pinhole_air = CalibratePinhole(air, truth, options);
    FlatPortAirOptions air_options;
    air_options.common = options;
    air_options.d_glass = 0.006;
    air_options.n_glass = 1.52;
    const auto in_air = CalibrateFlatPortInAir(air, pinhole_air, air_options);
    WaterRefinementOptions water_options;
    water_options.common = options;
    water_options.n_water = 1.333;
    const auto flat = CalibrateFlatPortJoint(air, in_air, water, water_options);
    CameraCalibrationOptions pinhole_options;  // all five Brown coefficients, as Pin-Water
    pinhole_options.compute_covariance = false;
    const auto pin_water = CalibratePinhole(water, truth, pinhole_options);

    const double flat_near = FittedRms(flat.camera, near);
    const double pin_near = FittedRms(pin_water.camera, near);
    const double flat_far = FittedRms(flat.camera, check);
    const double pin_far = FittedRms(pin_water.camera, check);
    std::printf(
        "tilt %.0f deg: calibration rms flat %.4f / pinhole %.4f px; at 1 m flat %.4f / "
        "pinhole %.4f px; at 3 m flat %.4f / pinhole %.4f px\n",
        tilt, flat.rms_px, pin_water.rms_px, flat_near, pin_near, flat_far, pin_far);
    EXPECT_LT(flat_far, 0.05);           // within calibration noise (0.1 px corners)
    EXPECT_GT(pin_far, 3.0 * flat_far);  // the pinhole's range-dependent error
    EXPECT_GT(pin_far, pin_near);
  }
}

}  // namespace
}  // namespace uwscan
