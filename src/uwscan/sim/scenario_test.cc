// Scenarios: calibration image sets of §6.1 are usable by OpenCV's
// checkerboard detector and agree with their rig; the tilted laser of §6.2
// bends as the thesis describes; scene.yaml round-trips and is strict; the
// water presets are Petzold's measured waters.
#include "uwscan/sim/scenario.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "uwscan/sim/laser_port.h"
#include "uwscan/sim/scene_yaml.h"
#include "uwscan/util/error.h"

namespace uwscan::sim {
namespace {

TEST(ScenarioTest, AquariumCheckerboardsAreDetectedWhereTheirRigProjectsThem) {
  ScenarioOptions options;
  options.width = 640;
  options.height = 480;
  options.frames = 2;
  options.output = OutputFormat::kRgb;
  const Scenario scenario = MakeScenario("aquarium", options);
  ASSERT_EQ(scenario.calibration.size(), 2u);
  for (const CalibrationSet& set : scenario.calibration) {
    const Camera& camera = set.config.rig.cameras[0];
    EXPECT_EQ(camera.IsFlatPort(), set.name == "water") << set.name;
    const Renderer renderer(set.config);
    const Texture& board = set.config.scene.surfaces[0].texture;
    const cv::Size pattern(board.squares_x - 1, board.squares_y - 1);
    for (size_t v = 0; v < set.views.size(); ++v) {
      cv::Mat gray;
      cv::cvtColor(renderer.Render(set.views[v]).image, gray, cv::COLOR_BGR2GRAY);
      std::vector<cv::Point2f> corners;
      ASSERT_TRUE(cv::findChessboardCornersSB(gray, pattern, corners, cv::CALIB_CB_ACCURACY))
          << set.name << " view " << v;
      // Match each detection to the nearest projected true corner.
      const Rigid3d camera_from_world = set.views[v].world_from_camera.Inverse();
      double worst = 0, sum = 0;
      for (const auto& corner : corners) {
        double best = 1e9;
        for (int j = 1; j < board.squares_y; ++j) {
          for (int i = 1; i < board.squares_x; ++i) {
            const Eigen::Vector3d local((i - 0.5 * board.squares_x) * board.scale_m,
                                        (j - 0.5 * board.squares_y) * board.scale_m, 0);
            const auto pixel = camera.Project(camera_from_world * local);
            if (pixel)
              best = std::min(best, std::hypot(pixel->x() - corner.x, pixel->y() - corner.y));
          }
        }
        worst = std::max(worst, best);
        sum += best;
      }
      EXPECT_LT(worst, 0.5) << set.name << " view " << v;
      EXPECT_LT(sum / corners.size(), 0.15) << set.name << " view " << v;
    }
  }
}

TEST(ScenarioTest, TiltedLaserPortBendsTheSheetMoreWithTilt) {
  // The bare laser's port tilted about the line direction (§4.3, §6.2).
  auto fit_at = [](double tilt_deg) {
    const double t = tilt_deg * M_PI / 180;
    FlatPort port;
    port.normal = Eigen::Vector3d(0, std::sin(t), std::cos(t));
    port.d_air = 0.01;
    port.d_glass = 0.008;
    port.n_glass = 1.52;
    port.n_water = 1.333;
    return FitLaserBehindPort(port, 0.8, 0.2, 0.6);
  };
  const LaserPortFit straight = fit_at(0), five = fit_at(5), ten = fit_at(10);
  EXPECT_LT(std::abs(straight.p1), 1e-9);  // orthogonal: the sheet stays a plane
  EXPECT_LT(straight.max_m, 1e-9);
  EXPECT_GT(std::abs(five.p1), 0.01);
  EXPECT_GT(std::abs(ten.p1), 1.8 * std::abs(five.p1));
  // The eq. 4.30 cone describes the refracted sheet to micrometres.
  EXPECT_LT(ten.rms_m, 2e-5);

  ScenarioOptions options;
  options.width = 160;
  options.height = 120;
  options.laser_tilt_deg = 5;
  const Scenario scenario = MakeScenario("laser-tilt", options);
  EXPECT_NEAR(std::abs(scenario.config.rig.lasers[0].p1), std::abs(five.p1),
              1e-9);  // sign: axis convention
  ASSERT_EQ(scenario.calibration.size(), 1u);
  EXPECT_EQ(scenario.calibration[0].name, "laser");
  const Renderer renderer(scenario.calibration[0].config);
  for (const FrameState& view : scenario.calibration[0].views) {
    EXPECT_GT(renderer.LaserGroundTruth(view).size(), 60u);
  }
}

TEST(ScenarioTest, SceneYamlRoundTripsForEveryScenario) {
  for (const std::string& name : ScenarioNames()) {
    ScenarioOptions options;
    options.width = 64;
    options.height = 48;
    options.frames = 2;
    const Scenario scenario = MakeScenario(name, options);
    const std::string text = SceneToYaml(scenario);
    const Scenario back = ParseSceneYaml(text, name, scenario.config.rig);
    EXPECT_EQ(SceneToYaml(back), text) << name;
  }
}

TEST(ScenarioTest, SceneYamlIsStrict) {
  ScenarioOptions options;
  options.width = 64;
  options.height = 48;
  const Scenario scenario = MakeScenario("tank-target", options);
  const std::string text = SceneToYaml(scenario);
  auto error_of = [&](const std::string& changed) -> std::string {
    try {
      ParseSceneYaml(changed, "scene.yaml", scenario.config.rig);
    } catch (const Error& e) {
      return e.what();
    }
    return "";
  };
  std::string unknown = text;
  unknown.replace(unknown.find("  phase_g:"), 0, "  colour: blue\n");
  EXPECT_NE(error_of(unknown).find("unknown key 'medium.colour'"), std::string::npos)
      << error_of(unknown);
  std::string missing = text;
  missing.erase(missing.find("  phase_g:"),
                missing.find('\n', missing.find("  phase_g:")) - missing.find("  phase_g:") + 1);
  EXPECT_NE(error_of(missing).find("missing key 'medium.phase_g'"), std::string::npos);
  std::string bad = text;
  bad.replace(bad.find("rig_laser: laser0"), 17, "rig_laser: laser9");
  EXPECT_NE(error_of(bad).find("laser9"), std::string::npos);
}

TEST(MediumTest, PresetsArePetzoldsWatersAt530) {
  EXPECT_NEAR(Medium::Preset("clear").Attenuation(530), 0.151, 1e-12);
  EXPECT_NEAR(Medium::Preset("coastal").Attenuation(530), 0.398, 1e-12);
  EXPECT_NEAR(Medium::Preset("turbid").Attenuation(530), 2.190, 1e-12);
  EXPECT_NEAR(Medium::Preset("clear").Scattering(530), 0.037, 1e-12);
  EXPECT_NEAR(Medium::Preset("turbid").Scattering(530), 1.824, 1e-12);
  EXPECT_NEAR(Medium::Preset("pure").Attenuation(530), PureWaterAbsorption(530), 0);
  EXPECT_EQ(Medium::Preset("air").Attenuation(530), 0.0);
  // Numbers are c_p(530); attenuation grows with it at every wavelength.
  for (double wavelength : {450.0, 530.0, 620.0}) {
    EXPECT_LT(Medium::Parse("0.2").Attenuation(wavelength),
              Medium::Parse("0.5").Attenuation(wavelength));
  }
  EXPECT_THROW(Medium::Parse("-1"), Error);
  EXPECT_THROW(Medium::Parse("murky"), Error);
  EXPECT_THROW(Medium::Parse("nan"), Error);
}

TEST(ScenarioTest, MarineSnowAddsLocalisedParticlesDeterministically) {
  ScenarioOptions options;
  options.width = 320;
  options.height = 240;
  options.output = OutputFormat::kRgb;
  Scenario clean = MakeScenario("tank-target", options);
  clean.config.sensor.noise = false;
  options.marine_snow_per_m3 = 300;
  Scenario snowy = MakeScenario("tank-target", options);
  snowy.config.sensor.noise = false;
  const Trajectory trajectory(clean.motion);
  const FrameState state = clean.FrameAt(trajectory, 5);
  const cv::Mat a = Renderer(clean.config).Render(state).electrons;
  const cv::Mat b = Renderer(snowy.config).Render(state).electrons;
  cv::Mat difference = b - a, changed;
  double lowest = 0;
  cv::minMaxLoc(difference.reshape(1), &lowest);
  EXPECT_GE(lowest, 0.0);  // only adds light
  cv::compare(difference.reshape(1), 1.0, changed, cv::CMP_GT);
  const double share = cv::countNonZero(changed) / static_cast<double>(changed.total());
  EXPECT_GT(share, 0.001);
  EXPECT_LT(share, 0.2);
  EXPECT_EQ(cv::norm(b, Renderer(snowy.config).Render(state).electrons, cv::NORM_INF), 0.0);
}

TEST(ScenarioTest, MotionBlurSmoothsTheImage) {
  ScenarioOptions options;
  options.width = 320;
  options.height = 240;
  options.output = OutputFormat::kRgb;
  Scenario scenario = MakeScenario("tank-target", options);
  scenario.config.sensor.noise = false;
  const Renderer renderer(scenario.config);
  FrameState sharp = scenario.FrameAt(Trajectory(scenario.motion), 0);
  FrameState blurred = sharp;
  for (int k = 0; k < 8; ++k) {
    Rigid3d pose = sharp.world_from_camera;
    pose.translation.x() += 0.04 * (k / 7.0 - 0.5);  // 4 cm during the exposure
    blurred.exposure_poses.push_back(pose);
  }
  auto gradient_energy = [&](const FrameState& state) {
    cv::Mat gray, dx;
    cv::extractChannel(renderer.Render(state).electrons, gray, 0);
    cv::Sobel(gray, dx, CV_32F, 1, 0);
    return cv::norm(dx, cv::NORM_L2);
  };
  EXPECT_LT(gradient_energy(blurred), 0.8 * gradient_energy(sharp));
}

TEST(ScenarioTest, BoxFilteredTexturesMatchSupersampling) {
  // One ray per pixel with box-filtered textures vs. 4x4 rays per pixel.
  ScenarioOptions options;
  options.width = 320;
  options.height = 240;
  options.output = OutputFormat::kRgb;
  Scenario scenario = MakeScenario("tank-target", options);
  scenario.config.sensor.noise = false;
  const FrameState state = scenario.FrameAt(Trajectory(scenario.motion), 0);
  const cv::Mat single = Renderer(scenario.config).Render(state).electrons;
  scenario.config.render.supersample = 4;
  const RenderedFrame super = Renderer(scenario.config).Render(state);
  cv::Mat red_single, red_super;
  cv::extractChannel(single, red_single, 0);
  cv::extractChannel(super.electrons, red_super, 0);
  const double mean = cv::mean(red_super)[0];
  EXPECT_LT(cv::norm(red_single, red_super, cv::NORM_L1) / red_super.total(), 0.03 * mean);
  EXPECT_LT(std::abs(cv::mean(red_single)[0] - mean), 0.01 * mean);
  EXPECT_NEAR(super.range_m.at<float>(120, 160), 2.0, 0.2);
}

TEST(ScenarioTest, BadOptionsAreRejected) {
  ScenarioOptions options;
  options.frames = 0;
  EXPECT_THROW(MakeScenario("tank-target", options), Error);
  options = {};
  options.width = 64;  // without height
  EXPECT_THROW(MakeScenario("tank-target", options), Error);
  options = {};
  options.turbidity = "-0.5";
  EXPECT_THROW(MakeScenario("tank-target", options), Error);
  EXPECT_THROW(MakeScenario("wreck", ScenarioOptions{}), UsageError);
}

// --gain sets every scenario's analog gain (default 4): the digitised
// image scales with it, and a gain out of range is rejected.
TEST(ScenarioTest, GainScalesTheDigitisedImage) {
  ScenarioOptions options;
  options.width = 640;  // (at 160x120 the pixels are 16x larger in area and most of it clips)
  options.height = 480;
  options.output = OutputFormat::kMono;
  for (const std::string& name : ScenarioNames())
    EXPECT_DOUBLE_EQ(MakeScenario(name, options).config.sensor.gain, kDefaultGain) << name;
  Scenario scenario = MakeScenario("tank-target", options);
  scenario.config.sensor.noise = false;
  const FrameState state = scenario.FrameAt(Trajectory(scenario.motion), 0);
  const RenderedFrame frame = Renderer(scenario.config).Render(state);
  const auto mean_grey = [&](double gain) {
    options.gain = gain;
    const Scenario with_gain = MakeScenario("tank-target", options);
    EXPECT_DOUBLE_EQ(with_gain.config.sensor.gain, gain);
    SensorOptions sensor = with_gain.config.sensor;
    sensor.noise = false;
    return cv::mean(Digitize(frame.electrons, sensor, "", 1, 1))[0];
  };
  const double low = mean_grey(1.0), high = mean_grey(2.0);
  EXPECT_GT(low, 5.0);
  EXPECT_NEAR(high / low, 2.0, 0.1);  // rounding, and the few pixels the line clips
  options.gain = 0.5;
  EXPECT_THROW(MakeScenario("tank-target", options), Error);
}

// --exposure-ms sets the shutter time of every scenario (default the
// sensor's 6.94 ms): the light gathered scales with it, the calibration
// sets' too; longer than the scenario's frame period is refused.
TEST(ScenarioTest, ExposureScalesTheLightGathered) {
  ScenarioOptions options;
  options.width = 320;
  options.height = 240;
  options.output = OutputFormat::kMono;
  const double default_s = SensorOptions{}.exposure_s;
  for (const std::string& name : ScenarioNames())
    EXPECT_DOUBLE_EQ(MakeScenario(name, options).config.sensor.exposure_s, default_s) << name;
  const auto mean_electrons = [&](double exposure_ms) {
    options.exposure_ms = exposure_ms;
    Scenario scenario = MakeScenario("tank-target", options);
    EXPECT_DOUBLE_EQ(scenario.config.sensor.exposure_s, exposure_ms * 1e-3);
    scenario.config.sensor.noise = false;
    const FrameState state = scenario.FrameAt(Trajectory(scenario.motion), 0);
    return cv::mean(Renderer(scenario.config).Render(state).electrons)[0];
  };
  const double full = mean_electrons(6.0), half = mean_electrons(3.0);
  EXPECT_GT(full, 100.0);
  EXPECT_NEAR(half / full, 0.5, 1e-6);
  options.exposure_ms = 2.0;
  for (const auto& set : MakeScenario("laser-tilt", options).calibration)
    EXPECT_DOUBLE_EQ(set.config.sensor.exposure_s, 2e-3) << set.name;
  options.exposure_ms = 7.0;  // 144 Hz: a frame lasts 6.94 ms
  EXPECT_THROW(MakeScenario("tank-target", options), UsageError);
  EXPECT_NO_THROW(MakeScenario("hull", options));  // 50 Hz
  for (const double bad : {0.0, -1.0, std::nan(""), 2000.0}) {
    options.exposure_ms = bad;
    EXPECT_THROW(MakeScenario("hull", options), Error) << bad;
  }
}

// The gain that gives a smaller image (the sensor binned, its pixels
// larger) the grey levels of the thesis camera's 1280x960 at the default
// gain: 4 there, 1 at 640 (4x the light per pixel), never below 1.
TEST(ScenarioTest, GainOfTheThesisImage) {
  EXPECT_DOUBLE_EQ(GainOfTheThesisImage(1280), kDefaultGain);
  EXPECT_DOUBLE_EQ(GainOfTheThesisImage(640), 1.0);
  EXPECT_DOUBLE_EQ(GainOfTheThesisImage(320), 1.0);
  EXPECT_DOUBLE_EQ(GainOfTheThesisImage(2560), 16.0);
  EXPECT_NEAR(GainOfTheThesisImage(960), kDefaultGain * 0.5625, 1e-12);
}

// --port-gap-mm moves the scanner scenarios' lens back from the window
// (default Tab. 6.3's 7 mm): the rig written with the dataset carries the
// gap, and the image of a floor point 2 m below moves outwards with it.
TEST(ScenarioTest, PortGapAppliesToTheScannerScenarios) {
  ScenarioOptions options;
  const Camera thesis = MakeScenario("seabed-transect", options).config.rig.cameras.front();
  EXPECT_DOUBLE_EQ(thesis.port.d_air, 0.007);
  options.port_gap_mm = 30.0;
  for (const std::string name : {"seabed-transect", "tank-target", "hull"}) {
    const Camera deep = MakeScenario(name, options).config.rig.cameras.front();
    EXPECT_DOUBLE_EQ(deep.port.d_air, 0.030) << name;
  }
  const Camera deep = MakeScenario("seabed-transect", options).config.rig.cameras.front();
  const Eigen::Vector3d corner(1.0, 0.7, 2.0);  // near the image corner at 2 m
  const auto a = thesis.Project(corner), b = deep.Project(corner);
  ASSERT_TRUE(a && b);
  // Further from the window the ray leaves the glass further out, so the
  // same point needs a smaller angle in air: it images closer to the centre.
  const Eigen::Vector2d centre(thesis.intrinsics[2], thesis.intrinsics[3]);
  EXPECT_LT((*b - centre).norm(), (*a - centre).norm() - 1.0);  // ~2 px at 1280x960
  options.port_gap_mm = -1.0;
  EXPECT_THROW(MakeScenario("seabed-transect", options), Error);
}

// The painted stripe of tank-target: full paint on the stripe, a footprint
// half on it gets half, none beside it; scene.yaml keeps it.
TEST(ScenarioTest, PaintedStripeIsOnTheFloorAndInSceneYaml) {
  ScenarioOptions options;
  options.width = 64;
  options.height = 48;
  options.painted_stripe_m = 0.02;
  options.painted_stripe_colour = "yellow";
  const Scenario scenario = MakeScenario("tank-target", options);
  const Texture& floor = scenario.config.scene.surfaces.at(0).texture;
  ASSERT_EQ(floor.stripe_width_m, 0.02);
  const double c = floor.stripe_s_m;
  EXPECT_LT((floor.Albedo(c, 0.3, 0.001) - floor.stripe_albedo).norm(), 1e-12);
  const Eigen::Vector3d beside = floor.Albedo(c + 0.05, 0.3, 0.004);
  EXPECT_GT((beside - floor.stripe_albedo).norm(), 0.1);
  // A 4 mm footprint centred on the stripe's edge: half paint.
  const Eigen::Vector3d edge = floor.Albedo(c + 0.01, 0.3, 0.004);
  const Eigen::Vector3d no_paint = [&] {
    Texture plain = floor;
    plain.stripe_width_m = 0.0;
    return plain.Albedo(c + 0.01, 0.3, 0.004);
  }();
  EXPECT_LT((edge - 0.5 * (no_paint + floor.stripe_albedo)).norm(), 1e-9);
  const std::string text = SceneToYaml(scenario);
  EXPECT_NE(text.find("stripe: {width_m: 0.02"), std::string::npos);
  const Scenario back = ParseSceneYaml(text, "scene.yaml", scenario.config.rig);
  EXPECT_EQ(SceneToYaml(back), text);
  options.painted_stripe_colour = "purple";
  EXPECT_THROW(MakeScenario("tank-target", options), Error);
}

// Interleaved lasers: on in even frames only, and a laser-off frame has
// neither ground-truth laser points nor laser light in the image.
TEST(ScenarioTest, InterleavedLasersAreOffInOddFrames) {
  ScenarioOptions options;
  options.width = 160;
  options.height = 120;
  options.frames = 4;
  options.laser_interleave = true;
  const Scenario scenario = MakeScenario("tank-target", options);
  const Trajectory trajectory(scenario.motion);
  const Renderer renderer(scenario.config);
  const FrameState on = scenario.FrameAt(trajectory, 2), off = scenario.FrameAt(trajectory, 3);
  EXPECT_TRUE(on.lasers_on);
  EXPECT_FALSE(off.lasers_on);
  EXPECT_GT(renderer.LaserGroundTruth(on).size(), 50u);
  EXPECT_TRUE(renderer.LaserGroundTruth(off).empty());
  // The same frame rendered with and without the laser: the green signal
  // (electrons before noise) differs only where the line is.
  FrameState dark = on;
  dark.lasers_on = false;
  cv::Mat lit_channels[3], dark_channels[3];
  cv::split(renderer.Render(on).electrons, lit_channels);
  cv::split(renderer.Render(dark).electrons, dark_channels);
  const cv::Mat extra = lit_channels[1] - dark_channels[1];
  double max_extra = 0.0;
  cv::minMaxLoc(extra, nullptr, &max_extra);
  EXPECT_GT(max_extra, 100.0);
  EXPECT_LT(cv::countNonZero(extra > 0.05 * max_extra), extra.total() / 10);
  EXPECT_TRUE(MakeScenario("tank-target", ScenarioOptions{}).FrameAt(trajectory, 1).lasers_on);
  // scene.yaml keeps it, so the dataset re-renders the same.
  const std::string text = SceneToYaml(scenario);
  EXPECT_NE(text.find("laser_interleave: true"), std::string::npos);
  EXPECT_TRUE(ParseSceneYaml(text, "scene.yaml", scenario.config.rig).laser_interleave);
  EXPECT_EQ(SceneToYaml(MakeScenario("tank-target", ScenarioOptions{})).find("laser_interleave"),
            std::string::npos);
}

// Two pods (§6.5): camera 1 sits 0.79 m beside camera 0, exposes half a
// frame later with only its partner laser (laser1, in pod 0) on, and sees
// that line where the laser1 sheet meets the floor; laser0's line is not in
// its image. The rig it writes lists it and its laser first.
TEST(ScenarioTest, TwoPodsEachCameraSeesTheOtherPodsLine) {
  ScenarioOptions options;
  options.width = 320;
  options.height = 240;
  options.frames = 5;
  options.output = OutputFormat::kRgb;
  options.pods = 2;
  const Scenario scenario = MakeScenario("tank-target", options);
  ASSERT_EQ(scenario.Cameras(), 2u);
  ASSERT_EQ(scenario.config.rig.lasers.size(), 2u);
  const Trajectory trajectory(scenario.motion);
  const Rig& rig = scenario.config.rig;
  const Rigid3d camera0_from_camera1 =
      rig.cameras[0].rig_from_camera.Inverse() * rig.cameras[1].rig_from_camera;
  EXPECT_NEAR(camera0_from_camera1.translation.norm(), 0.80, 0.01);
  const FrameState state = scenario.FrameAt(trajectory, 2, 1);
  const Rigid3d expected =
      trajectory.WorldFromCamera(2.5 / scenario.frame_rate_hz) * camera0_from_camera1;
  EXPECT_LT((state.world_from_camera.translation - expected.translation).norm(), 1e-12);
  EXPECT_DOUBLE_EQ(state.laser_angles_rad.at(0), scenario.ServoAngle(2.5));

  const SimConfig seen = scenario.CameraConfig(1);
  EXPECT_EQ(seen.rig.cameras.front().name, "cam1");
  EXPECT_EQ(seen.rig.lasers.front().name, "laser1");
  ASSERT_EQ(seen.lasers.size(), 1u);
  const Renderer renderer(seen);
  const auto truth = renderer.LaserGroundTruth(state);
  ASSERT_GT(truth.size(), 100u);
  const Rigid3d laser_from_camera =
      renderer.CameraFromLaser(0, state.laser_angles_rad[0]).Inverse();
  const cv::Mat image = renderer.Render(state).image;
  int bright = 0;
  for (const LaserPoint& point : truth) {
    // On the floor (z = 0) or the board (5 mm above it) ...
    const Eigen::Vector3d world = state.world_from_camera * point.point_in_camera;
    EXPECT_LT(std::min(std::abs(world.z()), std::abs(world.z() - 0.005)), 1e-6);
    // ... and on laser1's sheet, seen from camera 1.
    const auto residual = seen.rig.lasers.front().SheetResidual(
        seen.rig.lasers.front().camera_from_laser * (laser_from_camera * point.point_in_camera));
    ASSERT_TRUE(residual.has_value());
    EXPECT_LT(std::abs(*residual), 1e-6);
    const cv::Vec3b bgr = image.at<cv::Vec3b>(static_cast<int>(std::lround(point.pixel.y())),
                                              static_cast<int>(std::lround(point.pixel.x())));
    bright += bgr[1] > 150;  // the red LED adds little to green
  }
  EXPECT_GT(bright, 0.8 * truth.size());
  // Where camera 0's laser would draw its line in camera 1's image, nothing.
  SimConfig both = seen;
  both.lasers.push_back(seen.lasers.front());
  both.lasers.back().rig_laser = 1;  // laser0
  FrameState both_state = state;
  both_state.laser_angles_rad.push_back(state.laser_angles_rad[0]);
  const auto laser0_line = Renderer(both).LaserGroundTruth(both_state);
  int other_line = 0, other_points = 0;
  for (const LaserPoint& point : laser0_line) {
    if (point.laser != 1) continue;
    ++other_points;
    const cv::Vec3b bgr = image.at<cv::Vec3b>(static_cast<int>(std::lround(point.pixel.y())),
                                              static_cast<int>(std::lround(point.pixel.x())));
    other_line += bgr[1] > 150;
  }
  ASSERT_GT(other_points, 50);
  EXPECT_LT(other_line, 0.05 * other_points);

  options.laser_interleave = true;
  EXPECT_THROW(MakeScenario("tank-target", options), Error);
  options.laser_interleave = false;
  EXPECT_THROW(MakeScenario("seabed-transect", options), Error);
  options.pods = 3;
  EXPECT_THROW(MakeScenario("tank-target", options), Error);
}

}  // namespace
}  // namespace uwscan::sim
