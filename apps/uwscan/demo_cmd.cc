// uwscan demo: the end-to-end self-referenced scan arrives with the fusion
// issue; until then the demo shows what the foundation computes.
#include <cmath>
#include <cstdio>

#include "commands.h"
#include "uwscan/eval/port_analysis.h"
#include "uwscan/sensor/camera.h"

namespace uwscan::cli {
namespace {

void RunDemo() {
  std::printf("uwscan demo: the simulated tank-target scan is not yet available in this build.\n");
  std::printf("Foundation check on the thesis cameras (Tab. 4.5), pinhole fitted at 3 m:\n");
  for (const auto& [name, camera] : {std::pair{"Flat1", Camera::Flat1()},
                                     std::pair{"Flat2", Camera::Flat2()},
                                     std::pair{"Flat3", Camera::Flat3()}}) {
    PinholeFitOptions options;
    options.grid_step_px = 40;
    const PinholeFit fit = FitPinholeToFlatPort(camera, options);
    const ErrorStats near = PinholeErrorAtDepth(camera, fit.pinhole, 1.0, 40);
    std::printf("  %s: pinhole error at 3 m max %.3f px, at 1 m max %.3f px\n", name,
                fit.at_fit.max_px, near.max_px);
  }
}

}  // namespace

void RegisterDemoCommand(CLI::App& app) {
  auto* demo = app.add_subcommand("demo", "Simulate, reconstruct and evaluate a scan");
  demo->callback([] { RunDemo(); });
}

}  // namespace uwscan::cli
