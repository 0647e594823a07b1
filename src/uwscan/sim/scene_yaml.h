// scene.yaml (format uwscan-scene/1): everything besides rig.yaml that
// defines a simulated dataset — surfaces with poses and textures, medium,
// lights (with the laser servo), sensor, renderer settings, motion and
// sequence length. Reading it back together with rig.yaml reproduces the
// scenario, so evaluation and tests can re-render or re-project the scene.
// Strict like rig.yaml: unknown or missing keys are errors naming the key.
// Format in docs/simulator.md.
#pragma once

#include <filesystem>
#include <string>

#include "uwscan/sim/scenario.h"

namespace uwscan::sim {

std::string SceneToYaml(const Scenario& scenario);
void WriteSceneYaml(const std::filesystem::path& path, const Scenario& scenario);

// The scenario (without calibration sets) on the given rig; laser sources
// name their rig laser, resolved against `rig`.
Scenario ParseSceneYaml(const std::string& text, const std::string& source, const Rig& rig);
Scenario ReadSceneYaml(const std::filesystem::path& path, const Rig& rig);
// DATASET/rig.yaml + DATASET/scene.yaml.
Scenario LoadDatasetScenario(const std::filesystem::path& dataset);

}  // namespace uwscan::sim
