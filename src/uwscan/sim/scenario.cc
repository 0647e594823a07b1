#include "uwscan/sim/scenario.h"

#include <Eigen/Geometry>
#include <cmath>

#include "uwscan/sim/laser_port.h"
#include "uwscan/sim/random.h"
#include "uwscan/util/error.h"

namespace uwscan::sim {
namespace {

constexpr double kDeg = M_PI / 180.0;

Eigen::Quaterniond FromRotationVector(const Eigen::Vector3d& rotation_vector) {
  const double angle = rotation_vector.norm();
  if (angle == 0) return Eigen::Quaterniond::Identity();
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, rotation_vector / angle));
}

// Rotation whose columns are the given axes (right-handed).
Eigen::Quaterniond FromAxes(const Eigen::Vector3d& x, const Eigen::Vector3d& y,
                            const Eigen::Vector3d& z) {
  Eigen::Matrix3d m;
  m << x, y, z;
  return Eigen::Quaterniond(m);
}

// Camera looking straight down from `altitude` above the world origin
// (camera x = world x, camera y = world -y).
Rigid3d LookingDown(const Eigen::Vector3d& position) {
  return Rigid3d(FromAxes({1, 0, 0}, {0, -1, 0}, {0, 0, -1}), position);
}

Surface Floor(uint64_t seed, double size_m) {
  Surface floor;
  floor.name = "floor";
  floor.type = SurfaceType::kPlane;
  floor.size_x = floor.size_y = size_m;
  floor.texture.type = TextureType::kNatural;
  floor.texture.albedo = {0.45, 0.42, 0.33};  // sand
  floor.texture.contrast = 0.7;
  floor.texture.scale_m = 0.8;
  floor.texture.octaves = 6;
  floor.texture.seed = SplitMix64(seed ^ 0xF1004);
  return floor;
}

Surface Checkerboard(const std::string& name, int squares_x, int squares_y, double square_m) {
  Surface board;
  board.name = name;
  board.type = SurfaceType::kPlane;
  board.size_x = (squares_x + 2) * square_m;  // one square of white margin
  board.size_y = (squares_y + 2) * square_m;
  board.texture.type = TextureType::kCheckerboard;
  board.texture.albedo = {0.85, 0.85, 0.85};
  board.texture.albedo_dark = {0.04, 0.04, 0.04};
  board.texture.scale_m = square_m;
  board.texture.squares_x = squares_x;
  board.texture.squares_y = squares_y;
  return board;
}

// The §6.4 sensor: thesis camera, the laser of Tab. 6.3 on a servo turning
// about its line direction, a red LED beside the camera.
void AddThesisScanner(const ScenarioOptions& options, int width, int height, SimConfig* config) {
  Camera camera = ThesisCamera(width, height);
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
  // Peak near 80 % of full scale on a grey target at 2 m in clear water.
  source.power_w = options.laser_power_w.value_or(0.003);
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
  config->sensor.gain = 4.0;
  config->render.threads = options.threads;
}

Scenario TankTarget(const ScenarioOptions& options) {
  Scenario s;
  s.name = "tank-target";
  const int width = options.width.value_or(1280), height = options.height.value_or(960);
  AddThesisScanner(options, width, height, &s.config);
  s.config.scene.surfaces.push_back(Floor(options.seed, 40.0));
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
  s.config.scene.surfaces.push_back(Floor(options.seed, 60.0));
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

// The camera behind the aquarium window of §6.1: the thesis camera with the
// window as its flat port, `gap_mm` between lens and glass (+ 4 mm from the
// focal point to the lens front, as estimated in §6.1), window tilted about
// the camera y axis.
Camera AquariumCamera(int width, int height, double gap_mm, double tilt_deg) {
  Camera camera = ThesisCamera(width, height);
  camera.port.normal = Eigen::Vector3d(std::sin(tilt_deg * kDeg), 0, std::cos(tilt_deg * kDeg));
  camera.port.d_air = (gap_mm + 4.0) * 1e-3;
  camera.port.d_glass = 0.008;
  camera.port.n_glass = 1.52;
  camera.port.n_water = 1.333;  // fresh water
  return camera;
}

// Camera `distance` m from a point near the board centre, within
// `max_angle` of the board normal (world z), random roll.
Rigid3d RandomView(Rng& rng, double min_distance, double max_distance, double max_angle,
                   const Eigen::Vector3d& centre) {
  const Eigen::Vector3d target =
      centre + Eigen::Vector3d(rng.Uniform(-0.02, 0.02), rng.Uniform(-0.02, 0.02), 0);
  const double polar = max_angle * std::sqrt(rng.Uniform()), azimuth = rng.Uniform(0, 2 * M_PI);
  const Eigen::Vector3d from_target(std::sin(polar) * std::cos(azimuth),
                                    std::sin(polar) * std::sin(azimuth), std::cos(polar));
  const Eigen::Vector3d position = target + rng.Uniform(min_distance, max_distance) * from_target;
  const Eigen::Vector3d z = (target - position).normalized();
  Eigen::Vector3d x = Eigen::Vector3d::UnitX() - z.dot(Eigen::Vector3d::UnitX()) * z;
  x.normalize();
  const Eigen::Vector3d y = z.cross(x);
  const Eigen::Quaterniond look = FromAxes(x, y, z);
  const double roll = rng.Uniform(-0.25, 0.25);
  return Rigid3d(look * Eigen::Quaterniond(Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ())),
                 position);
}

SimConfig CalibrationConfig(const Camera& camera, const ScenarioOptions& options,
                            const Medium& medium, double ambient) {
  SimConfig config;
  config.rig.cameras = {camera};
  config.medium = medium;
  config.ambient.irradiance_rgb = Eigen::Vector3d::Constant(ambient);
  const OutputFormat output = options.output.value_or(OutputFormat::kBayer);
  config.rig.cameras[0].bayer = output == OutputFormat::kBayer ? "rggb" : "none";
  config.sensor.output = output;
  config.sensor.bits = options.bits.value_or(8);
  config.sensor.pixel_pitch_m = 3.75e-6 * 1280.0 / camera.width;
  config.sensor.f_number = 2.0;
  config.sensor.gain = 4.0;
  config.render.threads = options.threads;
  return config;
}

Scenario Aquarium(const ScenarioOptions& options) {
  Scenario s;
  s.name = "aquarium";
  const int width = options.width.value_or(1280), height = options.height.value_or(960);
  const Camera water_camera = AquariumCamera(width, height, options.port_gap_mm.value_or(1.0),
                                             options.port_tilt_deg.value_or(0.0));
  Camera air_camera = water_camera;
  air_camera.model = CameraModelId::kPinhole;  // calibrated in air without the window (§6.1)
  const Medium water = Medium::Parse(options.turbidity.value_or("pure"));
  Surface board = Checkerboard("checkerboard", 9, 7, 0.025);
  s.config = CalibrationConfig(water_camera, options, water, 0.05);
  s.config.scene.surfaces = {board};
  s.motion.type = MotionType::kViews;
  s.frames = options.frames.value_or(10);
  s.frame_rate_hz = 1.0;
  Rng rng(StreamSeed(options.seed, 0xA0A));
  // Working range of the aquarium: up to 0.4 m (§6.1).
  for (int i = 0; i < s.frames; ++i)
    s.views.push_back(RandomView(rng, 0.25, 0.4, 0.5, Eigen::Vector3d::Zero()));
  for (const char* name : {"air", "water"}) {
    CalibrationSet set;
    set.name = name;
    const bool air = set.name == "air";
    set.config = CalibrationConfig(air ? air_camera : water_camera, options,
                                   air ? Medium::Preset("air") : water, air ? 0.02 : 0.05);
    set.config.scene.surfaces = {board};
    for (int i = 0; i < s.frames; ++i) {
      FrameState view;
      view.world_from_camera =
          RandomView(rng, air ? 0.35 : 0.25, air ? 0.6 : 0.4, 0.5, Eigen::Vector3d::Zero());
      view.noise_seed = StreamSeed(options.seed, air ? 0xA1 : 0xA2, static_cast<uint64_t>(i));
      set.views.push_back(view);
    }
    s.calibration.push_back(set);
  }
  return s;
}

Scenario LaserTilt(const ScenarioOptions& options) {
  Scenario s;
  s.name = "laser-tilt";
  const int width = options.width.value_or(1280), height = options.height.value_or(960);
  const Camera camera = AquariumCamera(width, height, 1.0, 0.0);
  s.config =
      CalibrationConfig(camera, options, Medium::Parse(options.turbidity.value_or("pure")), 0.02);
  // The bare laser 0.1 m beside the camera behind the same window, its line
  // along the camera y axis, turned by the tilt about that axis (§6.2).
  const double tilt = options.laser_tilt_deg.value_or(5.0) * kDeg;
  const Rigid3d camera_from_inner(FromAxes({0, 1, 0}, {-std::cos(tilt), 0, -std::sin(tilt)},
                                           {-std::sin(tilt), 0, std::cos(tilt)}),
                                  Eigen::Vector3d(0.1, 0, 0));
  FlatPort laser_port;
  laser_port.normal = camera_from_inner.rotation.conjugate() * Eigen::Vector3d::UnitZ();
  laser_port.d_air = 0.01;
  laser_port.d_glass = camera.port.d_glass;
  laser_port.n_glass = camera.port.n_glass;
  laser_port.n_water = camera.port.n_water;
  const double fan = 0.8;
  const LaserPortFit fit = FitLaserBehindPort(laser_port, fan, 0.2, 0.6);
  LineProjector laser;
  laser.name = "laser0";
  laser.camera_from_laser = camera_from_inner * fit.inner_from_model;
  laser.p1 = fit.p1;
  s.config.rig.lasers = {laser};
  LaserSource source;
  source.power_w = options.laser_power_w.value_or(0.0003);
  source.fan_angle_rad = fan;
  source.width_m = 0.002;
  source.divergence_rad = 0.002;
  s.config.lasers = {source};
  s.laser_port_fit_rms_m = fit.rms_m;
  s.laser_tilt_rad = tilt;
  // A large white target with a checkerboard for its pose, at two distances.
  Surface target = Checkerboard("target", 12, 8, 0.025);
  target.size_x = 0.6;
  target.size_y = 0.4;
  s.config.scene.surfaces = {target};
  s.motion.type = MotionType::kViews;
  s.frames = options.frames.value_or(10);
  s.frame_rate_hz = 1.0;
  Rng rng(StreamSeed(options.seed, 0x7117));
  auto view = [&](double distance) {
    const Eigen::Vector3d tilt_vector(rng.Uniform(-0.1, 0.1), rng.Uniform(-0.1, 0.1), 0);
    const Rigid3d down = LookingDown(Eigen::Vector3d(0.05, 0, distance));
    return Rigid3d(
        Eigen::Quaterniond(Eigen::AngleAxisd(tilt_vector.norm(), tilt_vector.normalized())) *
            down.rotation,
        down.translation);
  };
  // Frames: the target receding from 0.28 to 0.48 m; calib/laser: two distances.
  for (int i = 0; i < s.frames; ++i)
    s.views.push_back(view(0.28 + 0.2 * i / std::max(1, s.frames - 1)));
  CalibrationSet set;
  set.name = "laser";
  set.config = s.config;
  for (int i = 0; i < 6; ++i) {
    FrameState state;
    state.world_from_camera = view(i < 3 ? 0.3 : 0.45);
    state.laser_angles_rad = {0.0};
    state.noise_seed = StreamSeed(options.seed, 0x7118, static_cast<uint64_t>(i));
    set.views.push_back(state);
  }
  s.calibration.push_back(set);
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
  UWS_CHECK(motion_blur_samples >= 1 && motion_blur_samples <= 64,
            "--motion-blur must be 1..64 (got ", motion_blur_samples, ")");
  UWS_CHECK(
      std::isfinite(marine_snow_per_m3) && marine_snow_per_m3 >= 0 && marine_snow_per_m3 <= 10000,
      "--marine-snow must be in [0, 10000] particles per m^3 (got ", marine_snow_per_m3, ")");
}

double Scenario::ServoAngle(int frame) const {
  if (frames <= 1) return servo_start_rad;
  return servo_start_rad + (servo_end_rad - servo_start_rad) * frame / (frames - 1);
}

FrameState Scenario::FrameAt(const Trajectory& trajectory, int frame) const {
  FrameState state;
  state.world_from_camera = views.empty() ? trajectory.WorldFromCamera(TimeOf(frame))
                                          : views.at(static_cast<size_t>(frame));
  state.laser_angles_rad.assign(config.lasers.size(), 0.0);
  for (size_t i = 0; i < config.lasers.size(); ++i) {
    if (config.lasers[i].servo) state.laser_angles_rad[i] = ServoAngle(frame);
  }
  state.noise_seed = StreamSeed(seed, 0xF4A3E, static_cast<uint64_t>(frame));
  if (motion_blur_samples > 1 && views.empty()) {
    // Exposure centred on the frame time.
    const double exposure = config.sensor.exposure_s;
    for (int k = 0; k < motion_blur_samples; ++k) {
      const double t = TimeOf(frame) + exposure * ((k + 0.5) / motion_blur_samples - 0.5);
      state.exposure_poses.push_back(trajectory.WorldFromCamera(t));
    }
  }
  return state;
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
    scenario = Aquarium(options);
  } else if (name == "laser-tilt") {
    scenario = LaserTilt(options);
  } else {
    std::string list;
    for (const auto& known : ScenarioNames()) list += (list.empty() ? "" : ", ") + known;
    throw UsageError("unknown scenario '" + name + "' (one of: " + list + ")");
  }
  scenario.seed = options.seed;
  scenario.motion_blur_samples = options.motion_blur_samples;
  scenario.config.snow.per_m3 = options.marine_snow_per_m3;
  scenario.config.snow.seed = StreamSeed(options.seed, 0x5A0);
  scenario.config.Check();
  for (const auto& set : scenario.calibration) set.config.Check();
  return scenario;
}

}  // namespace uwscan::sim
