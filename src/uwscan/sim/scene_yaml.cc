#include "uwscan/sim/scene_yaml.h"

#include <fmt/format.h>

#include <fstream>
#include <sstream>

#include "uwscan/io/rig_yaml.h"
#include "uwscan/io/strict_yaml.h"
#include "uwscan/io/tum.h"
#include "uwscan/util/atomic_file.h"
#include "uwscan/util/error.h"

namespace uwscan::sim {
namespace {

constexpr const char* kFormat = "uwscan-scene/1";

const char* Bool(bool value) { return value ? "true" : "false"; }

void WriteTexture(const Texture& t, std::ostream& out) {
  out << "    texture:\n"
      << "      type: " << TextureName(t.type) << "\n"
      << "      albedo: " << YamlVector(t.albedo) << "\n"
      << "      albedo_dark: " << YamlVector(t.albedo_dark) << "\n"
      << "      contrast: " << YamlNumber(t.contrast) << "\n"
      << "      scale_m: " << YamlNumber(t.scale_m) << "\n"
      << "      octaves: " << t.octaves << "\n"
      << "      seed: " << t.seed << "\n"
      << "      squares: [" << t.squares_x << ", " << t.squares_y << "]\n";
  if (t.stripe_width_m > 0.0) {
    out << "      stripe: {width_m: " << YamlNumber(t.stripe_width_m)
        << ", s_m: " << YamlNumber(t.stripe_s_m);
    if (t.stripe_period_m > 0.0) out << ", period_m: " << YamlNumber(t.stripe_period_m);
    out << ", albedo: " << YamlVector(t.stripe_albedo) << "}\n";
  }
}

Texture ReadTexture(StrictMap map) {
  Texture t;
  t.type = TextureFromName(map.String("type"), map.source() + ": " + map.Name("type"));
  t.albedo = map.Vector3("albedo");
  t.albedo_dark = map.Vector3("albedo_dark");
  t.contrast = map.Number("contrast");
  t.scale_m = map.Number("scale_m");
  t.octaves = map.Integer("octaves");
  t.seed = map.Unsigned("seed");
  const YAML::Node squares = map.Get("squares");
  UWS_CHECK(squares.IsSequence() && squares.size() == 2, map.source(), ": '", map.Name("squares"),
            "' must be a list of 2 integers");
  t.squares_x = squares[0].as<int>();
  t.squares_y = squares[1].as<int>();
  if (map.Has("stripe")) {  // optional: a painted stripe
    StrictMap stripe = map.Child("stripe");
    t.stripe_width_m = stripe.Number("width_m");
    t.stripe_s_m = stripe.Number("s_m");
    if (stripe.Has("period_m")) t.stripe_period_m = stripe.Number("period_m");
    t.stripe_albedo = stripe.Vector3("albedo");
    stripe.CheckNoUnknownKeys();
  }
  map.CheckNoUnknownKeys();
  return t;
}

}  // namespace

std::string SceneToYaml(const Scenario& s) {
  const SimConfig& c = s.config;
  std::ostringstream out;
  out << "format: " << kFormat << "\n"
      << "# World frame: z up (the sea floor is z = 0 where there is one). Poses are\n"
      << "# a_from_b {q: [w, x, y, z], t: [x, y, z]} in metres; see docs/simulator.md.\n"
      << (s.motion.type == MotionType::kViews
              ? "# motion 'views': the per-frame poses are those of groundtruth.tum\n"
              : "")
      << "scenario: " << s.name << "\n"
      << "seed: " << s.seed << "\n"
      << "# laser behind its own port tilted by tilt_rad (laser-tilt); rig.yaml holds the\n"
      << "# eq. 4.30 model fitted to the exactly refracted sheet, fit_rms_m its distance\n"
      << "laser_port: {tilt_rad: " << YamlNumber(s.laser_tilt_rad)
      << ", fit_rms_m: " << YamlNumber(s.laser_port_fit_rms_m) << "}\n"
      << "sequence:\n"
      << "  frames: " << s.frames << "\n"
      << "  frame_rate_hz: " << YamlNumber(s.frame_rate_hz) << "\n"
      << "  motion_blur_samples: " << s.motion_blur_samples << "\n";
  if (s.laser_interleave) out << "  laser_interleave: true  # lasers on in even frames only\n";
  out << "surfaces:\n";
  for (const Surface& surface : c.scene.surfaces) {
    out << "  - name: " << surface.name << "\n"
        << "    type: " << SurfaceTypeName(surface.type) << "\n"
        << "    world_from_surface: " << YamlPose(surface.world_from_surface) << "\n"
        << "    size: [" << YamlNumber(surface.size_x) << ", " << YamlNumber(surface.size_y)
        << "]\n"
        << "    radius: " << YamlNumber(surface.radius) << "\n"
        << "    length: " << YamlNumber(surface.length) << "\n"
        << "    curvature: " << YamlNumber(surface.curvature) << "\n";
    WriteTexture(surface.texture, out);
  }
  const Medium& m = c.medium;
  out << "medium:\n"
      << "  name: " << m.name << "\n"
      << "  air: " << Bool(m.air) << "\n"
      << "  particle_attenuation_530: " << YamlNumber(m.particle_attenuation_530) << "\n"
      << "  phase_g: " << YamlNumber(m.phase_g) << "\n"
      << "  forward_fraction: " << YamlNumber(m.forward_fraction) << "\n"
      << "  forward_angle_rad: " << YamlNumber(m.forward_angle_rad) << "\n"
      << "  # derived beam attenuation c (1/m) for R G B, for reference only\n"
      << "  # attenuation_rgb: " << YamlVector(m.AttenuationRgb()) << "\n";
  out << "lasers:" << (c.lasers.empty() ? " []\n" : "\n");
  for (const LaserSource& l : c.lasers) {
    out << "  - rig_laser: " << c.rig.lasers.at(l.rig_laser).name << "\n"
        << "    power_w: " << YamlNumber(l.power_w) << "\n"
        << "    fan_angle_rad: " << YamlNumber(l.fan_angle_rad) << "\n"
        << "    width_m: " << YamlNumber(l.width_m) << "\n"
        << "    divergence_rad: " << YamlNumber(l.divergence_rad) << "\n"
        << "    # camera_from_laser(angle) = camera_from_laser(rig.yaml) * R(axis, angle) about "
           "pivot\n"
        << "    servo: {enabled: " << Bool(l.servo) << ", axis: " << YamlVector(l.servo_axis)
        << ", pivot: " << YamlVector(l.servo_pivot)
        << ", start_rad: " << YamlNumber(s.servo_start_rad)
        << ", end_rad: " << YamlNumber(s.servo_end_rad) << "}\n";
  }
  out << "floods:" << (c.floods.empty() ? " []\n" : "\n");
  for (const FloodLight& f : c.floods) {
    out << "  - name: " << f.name << "\n"
        << "    camera_from_light: " << YamlPose(f.camera_from_light) << "\n"
        << "    power_w: " << YamlNumber(f.power_w) << "\n"
        << "    wavelength_nm: " << YamlNumber(f.wavelength_nm) << "\n"
        << "    exponent: " << YamlNumber(f.exponent) << "\n";
  }
  out << "ambient: {irradiance_rgb: " << YamlVector(c.ambient.irradiance_rgb) << "}\n";
  out << "snow: {per_m3: " << YamlNumber(c.snow.per_m3)
      << ", max_range_m: " << YamlNumber(c.snow.max_range_m)
      << ", focus_m: " << YamlNumber(c.snow.focus_m) << ", seed: " << c.snow.seed << "}\n";
  const SensorOptions& n = c.sensor;
  out << "sensor:\n"
      << "  exposure_s: " << YamlNumber(n.exposure_s) << "\n"
      << "  f_number: " << YamlNumber(n.f_number) << "\n"
      << "  pixel_pitch_m: " << YamlNumber(n.pixel_pitch_m) << "\n"
      << "  quantum_efficiency: " << YamlNumber(n.quantum_efficiency) << "\n"
      << "  full_well_e: " << YamlNumber(n.full_well_e) << "\n"
      << "  read_noise_e: " << YamlNumber(n.read_noise_e) << "\n"
      << "  gain: " << YamlNumber(n.gain) << "\n"
      << "  bits: " << n.bits << "\n"
      << "  output: " << OutputFormatName(n.output) << "\n"
      << "  noise: " << Bool(n.noise) << "\n";
  const RenderOptions& r = c.render;
  out << "render:\n"
      << "  supersample: " << r.supersample << "\n"
      << "  laser_supersample: " << r.laser_supersample << "\n"
      << "  backscatter_step_px: " << r.backscatter_step_px << "\n"
      << "  backscatter_samples: " << r.backscatter_samples << "\n"
      << "  max_range_m: " << YamlNumber(r.max_range_m) << "\n"
      << "  forward_scatter: " << Bool(r.forward_scatter) << "\n"
      << "  backscatter: " << Bool(r.backscatter) << "\n"
      << "  shadows: " << Bool(r.shadows) << "\n";
  const MotionOptions& mo = s.motion;
  out << "motion:\n"
      << "  type: " << MotionTypeName(mo.type) << "\n"
      << "  world_from_camera_start: " << YamlPose(mo.world_from_camera_start) << "\n"
      << "  velocity_world: " << YamlVector(mo.velocity_world) << "\n"
      << "  amplitude_m: " << YamlNumber(mo.amplitude_m) << "\n"
      << "  amplitude_rad: " << YamlNumber(mo.amplitude_rad) << "\n"
      << "  bandwidth_hz: " << YamlNumber(mo.bandwidth_hz) << "\n"
      << "  seed: " << mo.seed << "\n";
  return out.str();
}

void WriteSceneYaml(const std::filesystem::path& path, const Scenario& scenario) {
  WriteFileAtomic(path, SceneToYaml(scenario));
}

Scenario ParseSceneYaml(const std::string& text, const std::string& source, const Rig& rig) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    UWS_THROW(source, ": not valid YAML: ", e.what());
  }
  StrictMap top(root, "", source);
  const std::string format = top.String("format");
  UWS_CHECK(format == kFormat, source, ": 'format' must be ", kFormat, " (got '", format, "')");
  Scenario s;
  s.name = top.String("scenario");
  s.seed = top.Unsigned("seed");
  StrictMap laser_port = top.Child("laser_port");
  s.laser_tilt_rad = laser_port.Number("tilt_rad");
  s.laser_port_fit_rms_m = laser_port.Number("fit_rms_m");
  laser_port.CheckNoUnknownKeys();
  StrictMap sequence = top.Child("sequence");
  s.frames = sequence.Integer("frames");
  s.frame_rate_hz = sequence.Number("frame_rate_hz");
  s.motion_blur_samples = sequence.Integer("motion_blur_samples");
  s.laser_interleave = sequence.Has("laser_interleave") && sequence.Bool("laser_interleave");
  sequence.CheckNoUnknownKeys();
  UWS_CHECK(s.frames >= 1 && s.frame_rate_hz > 0 && s.motion_blur_samples >= 1, source,
            ": sequence needs frames >= 1, frame_rate_hz > 0 and motion_blur_samples >= 1");

  const YAML::Node surfaces = top.Get("surfaces");
  UWS_CHECK(surfaces.IsSequence(), source, ": 'surfaces' must be a list");
  for (size_t i = 0; i < surfaces.size(); ++i) {
    StrictMap m(surfaces[i], "surfaces[" + std::to_string(i) + "]", source);
    Surface surface;
    surface.name = m.String("name");
    surface.type = SurfaceTypeFromName(m.String("type"), source + ": " + m.Name("type"));
    surface.world_from_surface = m.Pose("world_from_surface");
    const YAML::Node size = m.Get("size");
    UWS_CHECK(size.IsSequence() && size.size() == 2, source, ": '", m.Name("size"),
              "' must be a list of 2 numbers");
    surface.size_x = size[0].as<double>();  // checked by Surface::Check
    surface.size_y = size[1].as<double>();
    surface.radius = m.Number("radius");
    surface.length = m.Number("length");
    surface.curvature = m.Number("curvature");
    surface.texture = ReadTexture(m.Child("texture"));
    m.CheckNoUnknownKeys();
    s.config.scene.surfaces.push_back(surface);
  }

  StrictMap medium = top.Child("medium");
  s.config.medium.name = medium.String("name");
  s.config.medium.air = medium.Bool("air");
  s.config.medium.particle_attenuation_530 = medium.Number("particle_attenuation_530");
  s.config.medium.phase_g = medium.Number("phase_g");
  s.config.medium.forward_fraction = medium.Number("forward_fraction");
  s.config.medium.forward_angle_rad = medium.Number("forward_angle_rad");
  medium.CheckNoUnknownKeys();

  const YAML::Node lasers = top.Get("lasers");
  UWS_CHECK(lasers.IsSequence(), source, ": 'lasers' must be a list");
  for (size_t i = 0; i < lasers.size(); ++i) {
    StrictMap m(lasers[i], "lasers[" + std::to_string(i) + "]", source);
    LaserSource laser;
    const std::string rig_laser = m.String("rig_laser");
    laser.rig_laser = -1;
    for (size_t k = 0; k < rig.lasers.size(); ++k) {
      if (rig.lasers[k].name == rig_laser) laser.rig_laser = static_cast<int>(k);
    }
    UWS_CHECK(laser.rig_laser >= 0, source, ": '", m.Name("rig_laser"), "' names laser '",
              rig_laser, "' which the rig does not have");
    laser.power_w = m.Number("power_w");
    laser.fan_angle_rad = m.Number("fan_angle_rad");
    laser.width_m = m.Number("width_m");
    laser.divergence_rad = m.Number("divergence_rad");
    StrictMap servo = m.Child("servo");
    laser.servo = servo.Bool("enabled");
    laser.servo_axis = servo.Vector3("axis");
    laser.servo_pivot = servo.Vector3("pivot");
    s.servo_start_rad = servo.Number("start_rad");
    s.servo_end_rad = servo.Number("end_rad");
    servo.CheckNoUnknownKeys();
    m.CheckNoUnknownKeys();
    s.config.lasers.push_back(laser);
  }

  const YAML::Node floods = top.Get("floods");
  UWS_CHECK(floods.IsSequence(), source, ": 'floods' must be a list");
  for (size_t i = 0; i < floods.size(); ++i) {
    StrictMap m(floods[i], "floods[" + std::to_string(i) + "]", source);
    FloodLight flood;
    flood.name = m.String("name");
    flood.camera_from_light = m.Pose("camera_from_light");
    flood.power_w = m.Number("power_w");
    flood.wavelength_nm = m.Number("wavelength_nm");
    flood.exponent = m.Number("exponent");
    m.CheckNoUnknownKeys();
    s.config.floods.push_back(flood);
  }

  StrictMap ambient = top.Child("ambient");
  s.config.ambient.irradiance_rgb = ambient.Vector3("irradiance_rgb");
  ambient.CheckNoUnknownKeys();

  StrictMap snow = top.Child("snow");
  s.config.snow.per_m3 = snow.Number("per_m3");
  s.config.snow.max_range_m = snow.Number("max_range_m");
  s.config.snow.focus_m = snow.Number("focus_m");
  s.config.snow.seed = snow.Unsigned("seed");
  snow.CheckNoUnknownKeys();

  StrictMap sensor = top.Child("sensor");
  SensorOptions& n = s.config.sensor;
  n.exposure_s = sensor.Number("exposure_s");
  n.f_number = sensor.Number("f_number");
  n.pixel_pitch_m = sensor.Number("pixel_pitch_m");
  n.quantum_efficiency = sensor.Number("quantum_efficiency");
  n.full_well_e = sensor.Number("full_well_e");
  n.read_noise_e = sensor.Number("read_noise_e");
  n.gain = sensor.Number("gain");
  n.bits = sensor.Integer("bits");
  n.output = OutputFormatFromName(sensor.String("output"));
  n.noise = sensor.Bool("noise");
  sensor.CheckNoUnknownKeys();

  StrictMap render = top.Child("render");
  RenderOptions& r = s.config.render;
  r.supersample = render.Integer("supersample");
  r.laser_supersample = render.Integer("laser_supersample");
  r.backscatter_step_px = render.Integer("backscatter_step_px");
  r.backscatter_samples = render.Integer("backscatter_samples");
  r.max_range_m = render.Number("max_range_m");
  r.forward_scatter = render.Bool("forward_scatter");
  r.backscatter = render.Bool("backscatter");
  r.shadows = render.Bool("shadows");
  render.CheckNoUnknownKeys();

  StrictMap motion = top.Child("motion");
  MotionOptions& mo = s.motion;
  mo.type = MotionTypeFromName(motion.String("type"), source + ": motion.type");
  mo.world_from_camera_start = motion.Pose("world_from_camera_start");
  mo.velocity_world = motion.Vector3("velocity_world");
  mo.amplitude_m = motion.Number("amplitude_m");
  mo.amplitude_rad = motion.Number("amplitude_rad");
  mo.bandwidth_hz = motion.Number("bandwidth_hz");
  mo.seed = motion.Unsigned("seed");
  motion.CheckNoUnknownKeys();
  top.CheckNoUnknownKeys();

  s.config.rig = rig;
  try {
    s.config.Check();
    mo.Check("motion");
  } catch (const Error& e) {
    UWS_THROW(source, ": ", e.what());
  }
  return s;
}

Scenario ReadSceneYaml(const std::filesystem::path& path, const Rig& rig) {
  std::ifstream in(path);
  UWS_CHECK(in.good(), path.string(), ": cannot open for reading");
  std::stringstream text;
  text << in.rdbuf();
  return ParseSceneYaml(text.str(), path.string(), rig);
}

Scenario LoadDatasetScenario(const std::filesystem::path& dataset) {
  Scenario scenario = ReadSceneYaml(dataset / "scene.yaml", ReadRigYaml(dataset / "rig.yaml"));
  if (scenario.motion.type == MotionType::kViews) {
    for (const auto& pose : ReadTum(dataset / "groundtruth.tum"))
      scenario.views.push_back(pose.world_from_camera);
    UWS_CHECK(static_cast<int>(scenario.views.size()) == scenario.frames,
              (dataset / "groundtruth.tum").string(), ": ", scenario.views.size(),
              " poses but scene.yaml has ", scenario.frames, " frames");
  }
  return scenario;
}

}  // namespace uwscan::sim
