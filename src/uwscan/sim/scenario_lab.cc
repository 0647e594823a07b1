// The laboratory scenarios: aquarium (§6.1, flat-port calibration images in
// air and water) and laser-tilt (§6.2, a laser tilted behind its port).
#include <Eigen/Geometry>
#include <cmath>

#include "uwscan/sim/laser_port.h"
#include "uwscan/sim/scenario_parts.h"

namespace uwscan::sim::internal {

// The camera behind the aquarium window of §6.1: the thesis camera with the
// window as its flat port, `gap_mm` between lens and glass (+ 4 mm from the
// focal point to the lens front, as estimated in §6.1), window tilted about
// the camera y axis.
namespace {

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
  config.sensor.gain = options.gain.value_or(kDefaultGain);
  config.render.threads = options.threads;
  return config;
}

}  // namespace

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
  auto view = [&](double distance, double x) {
    const Eigen::Vector3d tilt_vector(rng.Uniform(-0.1, 0.1), rng.Uniform(-0.1, 0.1), 0);
    const Rigid3d down = LookingDown(Eigen::Vector3d(x, 0, distance));
    return Rigid3d(
        Eigen::Quaterniond(Eigen::AngleAxisd(tilt_vector.norm(), tilt_vector.normalized())) *
            down.rotation,
        down.translation);
  };
  // Frames: the target receding from 0.28 to 0.48 m, the line on the plain
  // target beside the checkerboard. calib/laser: two distances, the camera
  // over the checkerboard's centre so that the whole board is in view (its
  // 0.3 m width spans 46 of the 63 deg under-water field of view at 0.35 m,
  // plus up to 2 x 5.7 deg of random tilt).
  for (int i = 0; i < s.frames; ++i)
    s.views.push_back(view(0.28 + 0.2 * i / std::max(1, s.frames - 1), 0.05));
  CalibrationSet set;
  set.name = "laser";
  set.config = s.config;
  for (int i = 0; i < 6; ++i) {
    FrameState state;
    state.world_from_camera = view(i < 3 ? 0.35 : 0.5, 0.0);
    state.laser_angles_rad = {0.0};
    state.noise_seed = StreamSeed(options.seed, 0x7118, static_cast<uint64_t>(i));
    set.views.push_back(state);
  }
  s.calibration.push_back(set);
  return s;
}

}  // namespace uwscan::sim::internal
