#include "uwscan/sim/scenario.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "uwscan/sim/random.h"
#include "uwscan/sim/scenario_parts.h"
#include "uwscan/util/error.h"

namespace uwscan::sim {
namespace {

using internal::Checkerboard;
using internal::Floor;
using internal::FromAxes;
using internal::FromRotationVector;
using internal::LookingDown;

// The §6.4 sensor: thesis camera, the laser of Tab. 6.3 on a servo turning
// about its line direction, a red LED beside the camera.
void AddThesisScanner(const ScenarioOptions& options, int width, int height, SimConfig* config) {
  Camera camera = ThesisCamera(width, height);
  // A housing whose lens sits further behind the window (the thesis's
  // aquarium used 1, 10 and 20 mm, Tab. 6.1); the default is Tab. 6.3's.
  if (options.port_gap_mm) camera.port.d_air = *options.port_gap_mm * 1e-3;
  const OutputFormat output = options.output.value_or(OutputFormat::kBayer);
  camera.bayer = output == OutputFormat::kBayer ? "rggb" : "none";
  config->rig.cameras = {camera};
  LineProjector laser;
  laser.name = "laser0";
  laser.camera_from_laser =
      Rigid3d(FromRotationVector({-0.129, -0.104, 1.568}), Eigen::Vector3d(0.794, -0.001, 0.009));
  laser.p1 = -0.0203;
  laser.wavelength_nm = 532.0;
  config->rig.lasers = {laser};

  LaserSource source;
  source.rig_laser = 0;
  // 20 mW on the line: on a grey target at 2 m in clear water the core
  // saturates (as real lines often do); dark squares and turbid water do not.
  source.power_w = options.laser_power_w.value_or(0.02);
  source.fan_angle_rad = 1.2;
  source.width_m = 0.002;
  source.divergence_rad = 0.002;
  source.servo = true;
  source.servo_axis = Eigen::Vector3d::UnitX();
  config->lasers = {source};

  FloodLight led;
  led.name = "led_red";
  led.camera_from_light = Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(-0.15, 0.0, 0.0));
  led.power_w = 8.0;
  led.wavelength_nm = 630.0;
  led.exponent = 1.5;
  config->floods = {led};

  config->sensor.output = output;
  config->sensor.bits = options.bits.value_or(8);
  config->sensor.pixel_pitch_m = 3.75e-6 * 1280.0 / width;
  config->sensor.f_number = 2.0;
  config->sensor.gain = options.gain.value_or(kDefaultGain);
  config->render.threads = options.threads;
}

// The second pod of the §6.5 vehicle: pod 0 (camera 0, the LED, laser 1)
// mirrored across the plane halfway between the pods, 0.79 m to the side.
// Each camera uses the other pod's laser: the first laser (laser0, in pod
// 1) is camera 0's; the mirrored one (laser1, in pod 0, 10 cm beside
// camera 0) is camera 1's. The mirror keeps each camera's view of its line
// the same, mirrored left to right.
void AddSecondPod(SimConfig* config) {
  const Eigen::Matrix3d mirror = Eigen::Vector3d(-1, 1, 1).asDiagonal();
  const auto mirrored = [&](const Rigid3d& pose) {
    return Rigid3d(Eigen::Quaterniond(mirror * pose.rotation.toRotationMatrix() * mirror),
                   mirror * pose.translation);
  };
  Rig& rig = config->rig;
  const Rigid3d camera0_from_camera1(
      Eigen::Quaterniond::Identity(),
      {rig.lasers.front().camera_from_laser.translation.x(), 0.10, 0});
  Camera camera1 = rig.cameras.front();
  camera1.name = "cam1";
  camera1.rig_from_camera = rig.cameras.front().rig_from_camera * camera0_from_camera1;
  rig.cameras.push_back(camera1);
  LineProjector laser1 = rig.lasers.front();
  laser1.name = "laser1";
  laser1.camera_from_laser = camera0_from_camera1 * mirrored(rig.lasers.front().camera_from_laser);
  rig.lasers.push_back(laser1);
  LaserSource source1 = config->lasers.front();
  source1.rig_laser = 1;
  config->lasers.push_back(source1);
  // Two LEDs at half the power light the scene as the one did: the
  // exposure set for one pod does not saturate the red channel.
  config->floods.front().power_w *= 0.5;
  FloodLight led1 = config->floods.front();
  led1.name += "_pod1";
  led1.camera_from_light = camera0_from_camera1 * mirrored(led1.camera_from_light);
  config->floods.push_back(led1);
}

// Paint albedos: white, road-marking yellow, green.
Eigen::Vector3d StripeAlbedo(const std::string& colour) {
  if (colour == "green") return {0.08, 0.7, 0.15};
  if (colour == "yellow") return {0.85, 0.75, 0.1};
  return {0.9, 0.9, 0.9};
}

Scenario TankTarget(const ScenarioOptions& options) {
  Scenario s;
  s.name = "tank-target";
  const int width = options.width.value_or(1280), height = options.height.value_or(960);
  AddThesisScanner(options, width, height, &s.config);
  Surface floor = Floor(options.seed, 40.0);
  if (options.painted_stripe_m > 0) {
    // Beside the target, inside the laser's sweep (x -0.15 .. 0.7 m), along y
    // like the line.
    floor.texture.stripe_width_m = options.painted_stripe_m;
    floor.texture.stripe_s_m = -0.05;
    floor.texture.stripe_albedo = StripeAlbedo(options.painted_stripe_colour);
  }
  s.config.scene.surfaces.push_back(floor);
  Surface board = Checkerboard("checkerboard", 14, 10, 0.03);
  board.world_from_surface =
      Rigid3d(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.25, 0.0, 0.005));
  s.config.scene.surfaces.push_back(board);
  s.config.medium = Medium::Parse(options.turbidity.value_or("clear"));
  s.motion.type = MotionType::kHover;
  s.motion.world_from_camera_start = LookingDown({0.0, 0.0, 2.0});
  s.motion.amplitude_m = options.motion_amplitude.value_or(0.02);
  s.motion.amplitude_rad = s.motion.amplitude_m * 0.5;  // 0.01 rad per 2 cm
  s.motion.bandwidth_hz = 1.0;
  s.motion.seed = options.seed;
  s.frames = options.frames.value_or(60);
  s.frame_rate_hz = 144.0;
  // The sheet sweeps across the target from the laser side towards the
  // camera side.
  s.servo_start_rad = 0.10;
  s.servo_end_rad = -0.30;
  return s;
}

Scenario Hull(const ScenarioOptions& options) {
  Scenario s;
  s.name = "hull";
  const int width = options.width.value_or(1280), height = options.height.value_or(960);
  AddThesisScanner(options, width, height, &s.config);
  // World z up; the camera looks horizontally along +y at the hull.
  Surface hull;
  hull.name = "hull";
  hull.type = SurfaceType::kHull;
  hull.size_x = 4.0;       // along the arc (world z)
  hull.size_y = 8.0;       // along the ship (world x)
  hull.curvature = -0.25;  // convex towards the camera
  hull.world_from_surface =
      Rigid3d(FromAxes({0, 0, -1}, {1, 0, 0}, {0, -1, 0}), Eigen::Vector3d(0, 0.2, 0));
  hull.texture.type = TextureType::kNatural;
  hull.texture.albedo = {0.35, 0.33, 0.3};  // paint with fouling
  hull.texture.contrast = 0.5;
  hull.texture.scale_m = 0.6;
  hull.texture.octaves = 8;
  hull.texture.seed = SplitMix64(options.seed ^ 0x4011);
  Surface shaft;
  shaft.name = "shaft";
  shaft.type = SurfaceType::kCylinder;
  shaft.radius = 0.12;
  shaft.length = 4.0;
  shaft.world_from_surface =
      Rigid3d(FromAxes({0, 1, 0}, {0, 0, 1}, {1, 0, 0}), Eigen::Vector3d(0, -0.5, -0.35));
  shaft.texture.type = TextureType::kNatural;
  shaft.texture.albedo = {0.5, 0.45, 0.4};
  shaft.texture.contrast = 0.4;
  shaft.texture.scale_m = 0.2;
  shaft.texture.octaves = 6;
  shaft.texture.seed = SplitMix64(options.seed ^ 0x5AF7);
  s.config.scene.surfaces = {hull, shaft};
  s.config.medium = Medium::Parse(options.turbidity.value_or("coastal"));
  s.motion.type = MotionType::kHover;
  s.motion.world_from_camera_start =
      Rigid3d(FromAxes({1, 0, 0}, {0, 0, -1}, {0, 1, 0}), Eigen::Vector3d(0, -1.8, 0));
  s.motion.amplitude_m = options.motion_amplitude.value_or(0.03);
  s.motion.amplitude_rad = s.motion.amplitude_m * 0.5;
  s.motion.bandwidth_hz = 1.0;
  s.motion.seed = options.seed;
  s.frames = options.frames.value_or(60);
  s.frame_rate_hz = 50.0;
  s.servo_start_rad = 0.15;
  s.servo_end_rad = -0.35;
  return s;
}

Scenario SeabedTransect(const ScenarioOptions& options) {
  Scenario s;
  s.name = "seabed-transect";
  const int width = options.width.value_or(640), height = options.height.value_or(480);
  AddThesisScanner(options, width, height, &s.config);
  s.config.lasers.front().servo = false;
  Surface floor = Floor(options.seed, 60.0);
  if (options.painted_stripe_m > 0) {
    // Markings across the track every 2 m (survey tape, marker bands),
    // parallel to the laser line: they pass through it as the vehicle moves.
    floor.texture.stripe_width_m = options.painted_stripe_m;
    floor.texture.stripe_s_m = 1.0;
    floor.texture.stripe_period_m = 2.0;
    floor.texture.stripe_albedo = StripeAlbedo(options.painted_stripe_colour);
  }
  s.config.scene.surfaces.push_back(floor);
  Surface pipe;
  pipe.name = "pipeline";
  pipe.type = SurfaceType::kCylinder;
  pipe.radius = 0.25;
  pipe.length = 40.0;
  // Along world x, half buried, beside the track.
  pipe.world_from_surface =
      Rigid3d(FromAxes({0, 1, 0}, {0, 0, 1}, {1, 0, 0}), Eigen::Vector3d(10.0, -0.5, 0.05));
  pipe.texture.type = TextureType::kNatural;
  pipe.texture.albedo = {0.3, 0.35, 0.3};
  pipe.texture.contrast = 0.5;
  pipe.texture.scale_m = 0.3;
  pipe.texture.octaves = 6;
  pipe.texture.seed = SplitMix64(options.seed ^ 0x919E);
  s.config.scene.surfaces.push_back(pipe);
  s.config.medium = Medium::Parse(options.turbidity.value_or("clear"));
  s.motion.type = MotionType::kTransect;
  s.motion.world_from_camera_start = LookingDown({0.0, 0.0, 2.0});
  s.motion.velocity_world = Eigen::Vector3d(0.5, 0, 0);  // 20 m in 40 s
  s.motion.amplitude_m = options.motion_amplitude.value_or(0.02);
  s.motion.amplitude_rad = s.motion.amplitude_m * 0.5;
  s.motion.bandwidth_hz = 0.5;
  s.motion.seed = options.seed;
  s.frames = options.frames.value_or(200);
  s.frame_rate_hz = s.frames / 40.0;
  return s;
}

}  // namespace

const std::vector<std::string>& ScenarioNames() {
  static const std::vector<std::string> names = {"tank-target", "hull", "seabed-transect",
                                                 "aquarium", "laser-tilt"};
  return names;
}

void ScenarioOptions::Check() const {
  if (frames)
    UWS_CHECK(*frames >= 1 && *frames <= 1000000, "--frames must be >= 1 (got ", *frames, ")");
  if (width || height) {
    UWS_CHECK(width && height, "--width and --height must be given together");
    UWS_CHECK(*width >= 16 && *height >= 16 && *width <= 16384 && *height <= 16384,
              "--width/--height must be 16..16384 (got ", *width, "x", *height, ")");
  }
  if (turbidity) Medium::Parse(*turbidity);
  if (motion_amplitude) {
    UWS_CHECK(std::isfinite(*motion_amplitude) && *motion_amplitude >= 0 && *motion_amplitude <= 1,
              "--motion-amplitude must be in [0, 1] m (got ", *motion_amplitude, ")");
  }
  if (laser_power_w) {
    UWS_CHECK(std::isfinite(*laser_power_w) && *laser_power_w >= 0 && *laser_power_w <= 100,
              "--laser-power must be in [0, 100] W (got ", *laser_power_w, ")");
  }
  if (bits) UWS_CHECK(*bits == 8 || *bits == 12 || *bits == 16, "--bits must be 8, 12 or 16");
  if (gain) {
    UWS_CHECK(std::isfinite(*gain) && *gain >= 1 && *gain <= 1000,
              "--gain must be in [1, 1000] (got ", *gain, ")");
  }
  if (exposure_ms) {
    UWS_CHECK(std::isfinite(*exposure_ms) && *exposure_ms > 0 && *exposure_ms <= 1000,
              "--exposure-ms must be in (0, 1000] (got ", *exposure_ms, ")");
  }
  if (port_gap_mm) {
    UWS_CHECK(std::isfinite(*port_gap_mm) && *port_gap_mm >= 0 && *port_gap_mm <= 100,
              "--port-gap-mm must be in [0, 100] (got ", *port_gap_mm, ")");
  }
  if (port_tilt_deg) {
    UWS_CHECK(std::isfinite(*port_tilt_deg) && std::abs(*port_tilt_deg) <= 20,
              "--port-tilt-deg must be in [-20, 20] (got ", *port_tilt_deg, ")");
  }
  if (laser_tilt_deg) {
    UWS_CHECK(std::isfinite(*laser_tilt_deg) && std::abs(*laser_tilt_deg) <= 20,
              "--laser-tilt-deg must be in [-20, 20] (got ", *laser_tilt_deg, ")");
  }
  UWS_CHECK(threads >= 1 && threads <= 256, "--threads must be 1..256");
  UWS_CHECK(supersample >= 1 && supersample <= 8, "--supersample must be 1..8 (got ", supersample,
            ")");
  UWS_CHECK(motion_blur_samples >= 1 && motion_blur_samples <= 64,
            "--motion-blur must be 1..64 (got ", motion_blur_samples, ")");
  UWS_CHECK(
      std::isfinite(marine_snow_per_m3) && marine_snow_per_m3 >= 0 && marine_snow_per_m3 <= 10000,
      "--marine-snow must be in [0, 10000] particles per m^3 (got ", marine_snow_per_m3, ")");
  UWS_CHECK(std::isfinite(painted_stripe_m) && painted_stripe_m >= 0 && painted_stripe_m <= 0.5,
            "--painted-stripe must be in [0, 0.5] m (got ", painted_stripe_m, ")");
  UWS_CHECK(pods == 1 || pods == 2, "--pods must be 1 or 2 (got ", pods, ")");
  UWS_CHECK(pods == 1 || !laser_interleave,
            "--pods 2: the pods' lasers are paired, not interleaved");
  UWS_CHECK(painted_stripe_colour == "white" || painted_stripe_colour == "yellow" ||
                painted_stripe_colour == "green",
            "--stripe-colour must be white, yellow or green (got '", painted_stripe_colour, "')");
}

double Scenario::ServoAngle(double frame) const {
  if (frames <= 1) return servo_start_rad;
  return servo_start_rad + (servo_end_rad - servo_start_rad) * frame / (frames - 1);
}

FrameState Scenario::FrameAt(const Trajectory& trajectory, int frame, size_t camera) const {
  UWS_CHECK(camera < Cameras(), "scenario ", name, ": no camera ", camera);
  const Rigid3d camera0_from_camera = config.rig.CameraFromCamera(0, camera);
  const double time = TimeOf(frame, camera);
  FrameState state;
  state.world_from_camera =
      (views.empty() ? trajectory.WorldFromCamera(time) : views.at(static_cast<size_t>(frame))) *
      camera0_from_camera;
  // Camera k renders with its own laser source only (CameraConfig).
  const size_t sources = Cameras() > 1 ? 1 : config.lasers.size();
  state.laser_angles_rad.assign(sources, 0.0);
  for (size_t i = 0; i < sources; ++i) {
    const size_t source = Cameras() > 1 ? camera : i;
    if (config.lasers.at(source).servo)
      state.laser_angles_rad[i] = ServoAngle(time * frame_rate_hz);
  }
  state.lasers_on = !laser_interleave || frame % 2 == 0;
  state.noise_seed = camera == 0 ? StreamSeed(seed, 0xF4A3E, static_cast<uint64_t>(frame))
                                 : StreamSeed(seed, 0xF4A3E + camera, static_cast<uint64_t>(frame));
  if (motion_blur_samples > 1 && views.empty()) {
    // Exposure centred on the frame time.
    const double exposure = config.sensor.exposure_s;
    for (int k = 0; k < motion_blur_samples; ++k) {
      const double t = time + exposure * ((k + 0.5) / motion_blur_samples - 0.5);
      state.exposure_poses.push_back(trajectory.WorldFromCamera(t) * camera0_from_camera);
    }
  }
  return state;
}

SimConfig Scenario::CameraConfig(size_t camera) const {
  UWS_CHECK(camera < Cameras(), "scenario ", name, ": no camera ", camera);
  if (Cameras() == 1) return config;
  SimConfig view = config;
  view.rig = config.rig.Reordered(camera, camera);
  view.lasers = {config.lasers.at(camera)};
  view.lasers.front().rig_laser = 0;
  const Rigid3d camera_from_camera0 = config.rig.CameraFromCamera(camera, 0);
  for (FloodLight& flood : view.floods) {
    flood.camera_from_light = camera_from_camera0 * flood.camera_from_light;
  }
  return view;
}

Camera ThesisCamera(int width, int height) {
  // Tab. 6.3, Flat-Mixed: f 782.5 px, principal point (648.0, 484.8) at
  // 1280x960, d_air 7 mm, d_glass 10 mm, n = 1.0 / 1.77 / 1.337.
  Camera camera;
  camera.name = "cam0";
  camera.width = width;
  camera.height = height;
  const double sx = width / 1280.0, sy = height / 960.0;
  camera.intrinsics = {782.5 * sx, 782.5 * sy, 648.0 * sx, 484.8 * sy};
  camera.distortion = {-0.037, 0.0002, 0.0, 0.0, 0.0};
  camera.model = CameraModelId::kFlatPort;
  camera.port.normal = Eigen::Vector3d::UnitZ();
  camera.port.d_air = 0.007;
  camera.port.d_glass = 0.010;
  camera.port.n_air = 1.0;
  camera.port.n_glass = 1.77;
  camera.port.n_water = 1.337;
  return camera;
}

double GainOfTheThesisImage(int width) {
  UWS_CHECK(width > 0, "image width must be positive (got ", width, ")");
  const double light = std::pow(1280.0 / width, 2);  // per pixel, against the 1280-wide image
  return std::max(1.0, kDefaultGain / light);
}

Scenario MakeScenario(const std::string& name, const ScenarioOptions& options) {
  options.Check();
  Scenario scenario;
  if (name == "tank-target") {
    scenario = TankTarget(options);
  } else if (name == "hull") {
    scenario = Hull(options);
  } else if (name == "seabed-transect") {
    scenario = SeabedTransect(options);
  } else if (name == "aquarium") {
    scenario = internal::Aquarium(options);
  } else if (name == "laser-tilt") {
    scenario = internal::LaserTilt(options);
  } else {
    std::string list;
    for (const auto& known : ScenarioNames()) list += (list.empty() ? "" : ", ") + known;
    throw UsageError("unknown scenario '" + name + "' (one of: " + list + ")");
  }
  scenario.seed = options.seed;
  scenario.motion_blur_samples = options.motion_blur_samples;
  scenario.laser_interleave = options.laser_interleave;
  if (options.pods == 2) {
    if (name != "tank-target" && name != "hull") {
      throw UsageError("--pods 2: only tank-target and hull have the two-pod vehicle (got " + name +
                       ")");
    }
    AddSecondPod(&scenario.config);
  }
  if (options.exposure_ms) {
    // A camera cannot expose longer than a frame lasts.
    const double period_ms = 1000.0 / scenario.frame_rate_hz;
    UWS_USAGE_CHECK(*options.exposure_ms <= period_ms * (1 + 1e-9), "--exposure-ms ",
                    *options.exposure_ms, " is longer than ", name, "'s frame period (", period_ms,
                    " ms at ", scenario.frame_rate_hz, " Hz)");
    scenario.config.sensor.exposure_s = *options.exposure_ms * 1e-3;
    for (auto& set : scenario.calibration)
      set.config.sensor.exposure_s = scenario.config.sensor.exposure_s;
  }
  scenario.config.render.supersample = options.supersample;
  for (auto& set : scenario.calibration) set.config.render.supersample = options.supersample;
  scenario.config.snow.per_m3 = options.marine_snow_per_m3;
  scenario.config.snow.seed = StreamSeed(options.seed, 0x5A0);
  scenario.config.Check();
  for (const auto& set : scenario.calibration) set.config.Check();
  return scenario;
}

}  // namespace uwscan::sim
