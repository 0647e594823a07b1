// Streams a scenario into a dataset folder (architecture.md): rig.yaml,
// scene.yaml, frames/ + frames.csv (with laser angles), groundtruth.tum,
// laser_gt.csv and calib/ sets. Everything is written under a temporary
// sibling folder that is renamed into place at the end, so a failure never
// leaves partial output under the final name. Frames are rendered and
// written one at a time: memory does not grow with the sequence length.
#pragma once

#include <filesystem>
#include <string>

#include "uwscan/sim/scenario.h"

namespace uwscan::sim {

struct SimulateResult {
  int frames = 0;
  long laser_points = 0;
  double seconds = 0.0;
  double FramesPerSecond() const { return seconds > 0 ? frames / seconds : 0.0; }
};

// Throws uwscan::Error (bad output folder, write failure) after removing the
// temporary folder; `out_dir` must not exist or be an empty folder.
SimulateResult WriteDataset(const Scenario& scenario, const std::filesystem::path& out_dir,
                            bool progress = false);

SimulateResult SimulateScenario(const std::string& name, const ScenarioOptions& options,
                                const std::filesystem::path& out_dir, bool progress = false);

}  // namespace uwscan::sim
