// uwscan simulate SCENARIO --out DIR [options]: render a simulated dataset.
#include <cstdio>

#include "commands.h"
#include "uwscan/sim/simulate.h"
#include "uwscan/util/error.h"

namespace uwscan::cli {
namespace {

struct SimulateArgs {
  std::string scenario, out, turbidity, output;
  int frames = 0, width = 0, height = 0, bits = 0, threads = 2, motion_blur = 1, supersample = 1;
  double marine_snow = 0, painted_stripe = 0, gain = 0, exposure_ms = 0;
  std::string stripe_colour = "white";
  uint64_t seed = 1;
  double motion_amplitude = -1, laser_power = -1, port_gap_mm = 1, port_tilt_deg = 0,
         laser_tilt_deg = 5;
  bool quiet = false, laser_interleave = false;
  int pods = 1;
};

void RunSimulate(const SimulateArgs& args, const CLI::App& app) {
  sim::ScenarioOptions options;
  const auto given = [&app](const char* name) { return app.count(name) > 0; };
  if (given("--frames")) options.frames = args.frames;
  if (given("--width") || given("--height")) {
    if (!given("--width") || !given("--height"))
      throw UsageError("--width and --height go together");
    options.width = args.width;
    options.height = args.height;
  }
  options.seed = args.seed;
  if (given("--turbidity")) options.turbidity = args.turbidity;
  if (given("--motion-amplitude")) options.motion_amplitude = args.motion_amplitude;
  if (given("--laser-power")) options.laser_power_w = args.laser_power;
  if (given("--bits")) options.bits = args.bits;
  if (given("--gain")) options.gain = args.gain;
  if (given("--exposure-ms")) options.exposure_ms = args.exposure_ms;
  if (given("--port-gap-mm")) options.port_gap_mm = args.port_gap_mm;
  if (given("--port-tilt-deg")) options.port_tilt_deg = args.port_tilt_deg;
  if (given("--laser-tilt-deg")) options.laser_tilt_deg = args.laser_tilt_deg;
  options.threads = args.threads;
  options.motion_blur_samples = args.motion_blur;
  options.supersample = args.supersample;
  options.marine_snow_per_m3 = args.marine_snow;
  options.painted_stripe_m = args.painted_stripe;
  options.painted_stripe_colour = args.stripe_colour;
  options.laser_interleave = args.laser_interleave;
  options.pods = args.pods;
  try {
    if (given("--output")) options.output = sim::OutputFormatFromName(args.output);
    options.Check();
  } catch (const UsageError&) {
    throw;
  } catch (const Error& e) {
    throw UsageError(e.what());
  }
  const sim::Scenario scenario = sim::MakeScenario(args.scenario, options);
  const sim::SimulateResult result = sim::WriteDataset(scenario, args.out, !args.quiet);
  if (!args.quiet) {
    std::fprintf(stderr,
                 "uwscan: wrote %ld frames (%ld laser ground-truth points) to %s in %.1f s\n",
                 static_cast<long>(result.frames), static_cast<long>(result.laser_points),
                 args.out.c_str(), result.seconds);
  }
}

}  // namespace

void RegisterSimulateCommand(CLI::App& app) {
  auto args = std::make_shared<SimulateArgs>();
  auto* cmd = app.add_subcommand(
      "simulate", "Render a simulated underwater dataset with ground truth (docs/simulator.md)");
  cmd->add_option("scenario", args->scenario,
                  "tank-target | hull | seabed-transect | aquarium | laser-tilt")
      ->required();
  cmd->add_option("--out", args->out, "output dataset folder (must not exist or be empty)")
      ->required();
  cmd->add_option("--frames", args->frames, "number of frames (default per scenario)");
  cmd->add_option("--width", args->width, "image width in pixels (intrinsics scale along)");
  cmd->add_option("--height", args->height, "image height in pixels");
  cmd->add_option("--seed", args->seed, "random seed (motion, texture, noise)")
      ->capture_default_str();
  cmd->add_option("--turbidity", args->turbidity,
                  "air | pure | clear | coastal | turbid, or c_p(530 nm) in 1/m");
  cmd->add_option("--motion-amplitude", args->motion_amplitude, "rms platform motion per axis (m)");
  cmd->add_option("--laser-power", args->laser_power, "laser power on the line (W)");
  cmd->add_option("--output", args->output, "bayer | rgb | mono (default bayer)");
  cmd->add_option("--bits", args->bits, "8 | 12 | 16 bit quantisation (default 8)");
  cmd->add_option("--gain", args->gain,
                  "analog gain: full scale at 10,000 e- / gain (default 4; a mono camera "
                  "gathers about 3x the light of a colour one, so about 1.3 matches it)");
  cmd->add_option("--exposure-ms", args->exposure_ms,
                  "shutter time (ms; default 6.94, the frame period at 144 Hz; at most the "
                  "scenario's frame period): with --gain, what keeps a bright scene or smaller "
                  "images (larger pixels) from clipping");
  cmd->add_option("--port-gap-mm", args->port_gap_mm,
                  "lens-to-window gap (mm; aquarium 1, scanner scenarios 7)");
  cmd->add_option("--port-tilt-deg", args->port_tilt_deg, "aquarium: window tilt (deg)")
      ->capture_default_str();
  cmd->add_option("--laser-tilt-deg", args->laser_tilt_deg,
                  "laser-tilt: laser tilt behind the window (deg)")
      ->capture_default_str();
  cmd->add_option("--supersample", args->supersample, "n x n camera rays per pixel")
      ->capture_default_str();
  cmd->add_option("--motion-blur", args->motion_blur, "poses averaged over the exposure (1 = off)")
      ->capture_default_str();
  cmd->add_option("--marine-snow", args->marine_snow, "marine snow particles per m^3 (0 = off)")
      ->capture_default_str();
  cmd->add_option("--painted-stripe", args->painted_stripe,
                  "tank-target: width (m) of a painted stripe on the floor beside the target, "
                  "parallel to the laser line; seabed-transect: stripes across the track every "
                  "2 m (0 = none)")
      ->capture_default_str();
  cmd->add_option("--stripe-colour", args->stripe_colour, "white | yellow | green")
      ->capture_default_str();
  cmd->add_flag("--laser-interleave", args->laser_interleave,
                "lasers on in even frames only (frames.csv gets a laser_on column)");
  cmd->add_option("--pods", args->pods,
                  "tank-target, hull: 2 = the two-pod vehicle of thesis §6.5 (each camera uses the "
                  "other pod's laser; camera cam1's images in OUT/cam1/)")
      ->capture_default_str();
  cmd->add_option("--threads", args->threads, "render threads")->capture_default_str();
  cmd->add_flag("--quiet", args->quiet, "no progress bar or summary");
  cmd->callback([args, cmd] { RunSimulate(*args, *cmd); });
}

}  // namespace uwscan::cli
