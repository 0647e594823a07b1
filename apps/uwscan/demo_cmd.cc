// uwscan demo: simulate the thesis's tank experiment (§6.4), reconstruct it
// self-referenced with and without motion compensation, evaluate both
// against the simulator's truth and say where the cloud is.
#include <cstdio>
#include <filesystem>

#include "commands.h"
#include "uwscan/pipeline/evaluate_reconstruction.h"
#include "uwscan/pipeline/reconstruct.h"
#include "uwscan/sim/scenario.h"
#include "uwscan/sim/simulate.h"
#include "uwscan/util/atomic_file.h"
#include "uwscan/util/error.h"
#include "uwscan/util/interrupt.h"

namespace uwscan::cli {
namespace {
namespace fs = std::filesystem;

struct DemoArgs {
  std::string out = "uwscan-demo";
  // The thesis camera's resolution: the target's plane std is ~0.6 mm here,
  // ~1 mm at 640x480 (gain 1). About a minute here, most of it simulating.
  int frames = 200;
  int width = 1280;
  int height = 960;
  uint64_t seed = 1;
  bool quiet = false;
};

void RunDemo(const DemoArgs& args) {
  if (args.frames < 20) throw UsageError("--frames must be >= 20");
  UWS_USAGE_CHECK(args.width >= 320 && args.height >= 240,
                  "--width/--height must be at least 320x240 (got ", args.width, "x", args.height,
                  "): smaller, the laser line is under a pixel wide and the sensor's larger "
                  "pixels clip at its lowest gain (uwscan simulate makes any size)");
  const fs::path out(args.out);
  const fs::path dataset = out / "dataset";
  std::error_code error;
  // A demo run again replaces its own dataset, and nothing else: a folder
  // `dataset` under --out that is not a simulated one is the user's.
  if (fs::exists(dataset, error)) {
    UWS_CHECK(fs::exists(dataset / "scene.yaml", error), dataset.string(),
              ": exists and is not a simulated dataset (no scene.yaml); the demo replaces only "
              "its own: give another --out");
    fs::remove_all(dataset, error);
  }
  UWS_CHECK(!error, dataset.string(), ": cannot replace: ", error.message());
  InterruptibleScope interruptible;
  OutputFolder folder(out);  // removed again if the demo fails or is stopped before it fills it

  sim::ScenarioOptions options;
  options.frames = args.frames;
  options.width = args.width;
  options.height = args.height;
  options.seed = args.seed;
  // Another size is the same sensor binned, its pixels larger: the camera's
  // gain is set to the grey levels the scene was lit for at 1280x960, or the
  // red LED's colour clips on most of a smaller image and the odometry fails.
  options.gain = sim::GainOfTheThesisImage(args.width);
  std::printf(
      "uwscan demo: a hovering ROV scans a checkerboard on the sea floor at 2 m with a green\n"
      "laser on a servo and a red LED (thesis §6.4), %d frames at %dx%d, 144 Hz, gain %.3g.\n",
      args.frames, args.width, args.height, *options.gain);
  const auto simulated = sim::SimulateScenario("tank-target", options, dataset, !args.quiet);
  std::printf("1. simulated %d frames in %.1f s -> %s\n", simulated.frames, simulated.seconds,
              dataset.string().c_str());

  ReconstructJob job;
  job.dataset = dataset;
  job.out = out / "result";
  job.quiet = args.quiet;
  const ReconstructReport report = RunReconstruct(job);
  std::printf(
      "2. reconstructed %ld points from %d frames (%d without pose) in %.1f s, poses from %s\n",
      report.points, report.frames, report.frames_without_pose, report.seconds,
      report.pose_source.c_str());
  // What degraded it, as reconstruct says (a size or setting the scene's
  // light levels were not made for shows here).
  for (const std::string& warning : report.Warnings())
    std::printf("   warning: %s\n", warning.c_str());

  const ReconstructionEvaluation evaluation = EvaluateReconstruction(dataset, job.out);
  const SurfaceAccuracy* compensated = evaluation.compensated.Surface("checkerboard");
  const SurfaceAccuracy* uncompensated = evaluation.uncompensated.Surface("checkerboard");
  std::printf("3. against the simulator's truth (checkerboard target):\n");
  if (compensated && uncompensated && compensated->fitted && uncompensated->fitted) {
    std::printf("   plane std %.2f mm compensated vs %.2f mm uncompensated\n",
                compensated->fit_rms_m * 1e3, uncompensated->fit_rms_m * 1e3);
    if (compensated->distance_pairs > 0 && uncompensated->distance_pairs > 0) {
      std::printf("   distance error along the target %.2f %% vs %.2f %%\n",
                  compensated->distance_error_mean_pct, uncompensated->distance_error_mean_pct);
    }
  } else if (compensated && compensated->points > 0) {
    std::printf(
        "   the laser crossed the target in too few points to fit its plane (%ld): simulate "
        "more frames (--frames)\n",
        compensated->points);
  } else {
    std::printf("   the laser did not reach the target in this sequence\n");
  }
  if (evaluation.compensated.matched > 0 && evaluation.uncompensated.matched > 0) {
    std::printf("   point error (all surfaces) %.1f mm vs %.1f mm\n",
                evaluation.compensated.point_error_rms_m * 1e3,
                evaluation.uncompensated.point_error_rms_m * 1e3);
  }
  std::printf("cloud: %s (open with CloudCompare, MeshLab or Open3D)\n",
              (job.out / "cloud.ply").string().c_str());
  folder.Keep();
}

}  // namespace

void RegisterDemoCommand(CLI::App& app) {
  auto args = std::make_shared<DemoArgs>();
  auto* demo =
      app.add_subcommand("demo", "Simulate, reconstruct and evaluate a self-referenced scan");
  demo->add_option("--out", args->out, "output folder")->capture_default_str();
  demo->add_option("--frames", args->frames, "frames to simulate")->capture_default_str();
  demo->add_option("--width", args->width, "image width in pixels (intrinsics scale along)")
      ->capture_default_str();
  demo->add_option("--height", args->height, "image height in pixels")->capture_default_str();
  demo->add_option("--seed", args->seed, "random seed of the simulation (motion, texture, noise)")
      ->capture_default_str();
  demo->add_flag("--quiet", args->quiet, "no progress bars");
  demo->callback([args] { RunDemo(*args); });
}

}  // namespace uwscan::cli
