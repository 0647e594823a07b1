// Named scenarios (issue 3, thesis chapter 6): a scene, a rig, lights, a
// medium and a motion, ready to render frame by frame.
//   tank-target      §6.4: checkerboard (3 cm squares) on the sea floor at
//                    ~2 m, hovering ROV, green laser on a servo, red LED
//   hull             §6.5: hull section and propeller shaft, hovering
//   seabed-transect  textured floor with a pipeline, 2 m altitude, 20 m run
//   aquarium         §6.1: camera behind an aquarium window, checkerboard
//                    views in air (calib/air) and in water (calib/water)
//   laser-tilt       §6.2: laser tilted behind its own port, target at two
//                    distances (calib/laser)
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "uwscan/sim/motion.h"
#include "uwscan/sim/renderer.h"

namespace uwscan::sim {

const std::vector<std::string>& ScenarioNames();

// The scenarios' camera gain (ScenarioOptions::gain): 8-bit full scale at
// 2500 electrons, the line at 2 m in clear water 5.6x above it.
constexpr double kDefaultGain = 4.0;

// Unset fields take the scenario's default.
struct ScenarioOptions {
  std::optional<int> frames;
  std::optional<int> width, height;  // intrinsics scale with the resolution
  uint64_t seed = 1;
  std::optional<std::string> turbidity;    // preset or c_p(530) in 1/m
  std::optional<double> motion_amplitude;  // rms translation (m); rotation scales along
  std::optional<double> laser_power_w;
  std::optional<OutputFormat> output;
  std::optional<int> bits;
  // Analog gain: full scale at full_well_e / gain (default kDefaultGain; a
  // mono camera gathers about 3x the light of a colour one).
  std::optional<double> gain;
  // Shutter time (default SensorOptions' 6.94 ms, the thesis's 144 Hz);
  // at most the scenario's frame period.
  std::optional<double> exposure_ms;
  int threads = 2;
  // aquarium (§6.1): gap between lens and window (1, 10, 20 mm in the
  // thesis) and window tilt; the scanner scenarios (tank-target, hull,
  // seabed-transect) take the gap too (default Tab. 6.3's 7 mm);
  // laser-tilt (§6.2): laser tilt behind the window.
  std::optional<double> port_gap_mm, port_tilt_deg, laser_tilt_deg;
  int motion_blur_samples = 1;    // poses averaged over the exposure
  int supersample = 1;            // camera rays per pixel (n x n)
  double marine_snow_per_m3 = 0;  // particles per cubic metre (0 = none)
  // tank-target: a painted stripe on the floor beside the target, parallel
  // to the laser line and inside its sweep (a marking or tape that may look
  // like the line): width in metres (0 = none) and paint colour.
  double painted_stripe_m = 0;
  std::string painted_stripe_colour = "white";  // white | yellow | green
  // Lasers on in even frames only (thesis §5.4: detection on the difference
  // of consecutive on and off frames, features tracked without the line).
  bool laser_interleave = false;
  // tank-target, hull: 1, or 2 pods as on the §6.5 vehicle (each a camera
  // and a steerable laser, 0.8 m apart; each camera uses the other pod's
  // laser, the pulses paired so that it sees that line only).
  int pods = 1;

  void Check() const;  // throws uwscan::Error naming the option
};

// A set of calibration images (calib/NAME): its own rig and views.
struct CalibrationSet {
  std::string name;  // air | water | laser
  SimConfig config;
  std::vector<FrameState> views;
};

struct Scenario {
  std::string name;
  uint64_t seed = 1;  // noise and texture streams
  SimConfig config;
  MotionOptions motion;
  int frames = 10;
  double frame_rate_hz = 10.0;
  // Motion blur: poses sampled over the exposure (1 = none).
  int motion_blur_samples = 1;
  // Servo sweep of every laser source, linear from start to end over the
  // sequence (zero for lasers without servo).
  double servo_start_rad = 0.0, servo_end_rad = 0.0;
  bool laser_interleave = false;  // lasers on in even frames only
  std::vector<CalibrationSet> calibration;
  // Explicit per-frame poses (motion type kViews); frames = views.size().
  std::vector<Rigid3d> views;
  // laser-tilt: the tilt and how far the eq. 4.30 model is from the exactly
  // refracted sheet (informational, written as a comment in scene.yaml).
  double laser_tilt_rad = 0.0, laser_port_fit_rms_m = 0.0;

  // Several cameras (pods): camera k uses rig laser k and exposes k / n of
  // a frame interval after camera 0, while only its laser is on. The
  // trajectory is camera 0's; the others follow through the rig.
  size_t Cameras() const { return config.rig.cameras.size(); }
  double TimeOf(int frame, size_t camera = 0) const {
    return (frame + static_cast<double>(camera) / Cameras()) / frame_rate_hz;
  }
  double ServoAngle(double frame) const;
  // The frame's pose, servo angles and noise seed, for camera `camera`.
  FrameState FrameAt(const Trajectory& trajectory, int frame, size_t camera = 0) const;
  // What camera `camera` renders: the rig with it first (and its laser
  // first), its laser source only, the lights seen from it. With one camera,
  // the configuration itself.
  SimConfig CameraConfig(size_t camera) const;
};

// Throws uwscan::UsageError for an unknown name, uwscan::Error for bad options.
Scenario MakeScenario(const std::string& name, const ScenarioOptions& options);

// The thesis camera (Tab. 6.3, flat port) scaled to a resolution.
Camera ThesisCamera(int width, int height);

// The scenarios' sensor is the thesis camera's binned to the image size: a
// pixel of an image `width` wide is 1280 / width times as wide, and gathers
// the square of that in light. The analog gain that gives it the grey levels
// of the 1280-wide image at the default gain, as an operator would set it,
// but not below the lowest, 1 (below 640 px the pixels get more light).
double GainOfTheThesisImage(int width);

}  // namespace uwscan::sim
