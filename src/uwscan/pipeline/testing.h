// Simulated scans for the pipeline's tests: each test simulates what it
// needs into a temporary folder of its own and reconstructs it.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "uwscan/pipeline/reconstruct.h"
#include "uwscan/sim/scenario.h"
#include "uwscan/sim/simulate.h"

namespace uwscan::pipeline_testing {

// The self-referenced odometry as before its robust loss at the tracks'
// noise: the plain odometry's options (Huber at 1.5 px), its BAs at their
// 10 iterations throughout. For tests whose premise is a harm that loss
// mends (BENCHMARKS.md, "A robust loss at the tracks' noise").
inline void UseOdometryBeforeTheRobustLoss(fusion::SelfReferencedOptions* options) {
  options->odometry = vo::OdometryOptions();
  options->running_ba_iterations = options->odometry.ba.max_iterations;
}

// The passive image tracked linear, as before it was tracked in logarithm
// (SelfReferencedOptions::log_offset_fraction 0): for tests whose premise
// is a harm the logarithm mends too, or that compare other settings on the
// image they were written on (BENCHMARKS.md, "The tracked image in
// logarithm").
inline void UseLinearTrackedImage(fusion::SelfReferencedOptions* options) {
  options->log_offset_fraction = 0.0;
}

// A simulated scan's size, length and seed; the rest the scenario's own.
inline sim::ScenarioOptions ScanOptions(int width, int height, int frames, uint64_t seed) {
  sim::ScenarioOptions options;
  options.width = width;
  options.height = height;
  options.frames = frames;
  options.seed = seed;
  return options;
}

// A file's bytes, to compare outputs byte for byte ("" if it cannot be read).
inline std::string FileBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// An empty temporary folder of this test process.
inline std::filesystem::path TempFolder(const std::string& name) {
  const std::filesystem::path root = std::filesystem::temp_directory_path() /
                                     ("uwscan_" + name + "_test_" + std::to_string(::getpid()));
  std::filesystem::remove_all(root);
  return root;
}

// `scenario` simulated into root/data, and a quiet job on it.
inline ReconstructJob SimulatedJob(const std::filesystem::path& root, const std::string& scenario,
                                   const sim::ScenarioOptions& options) {
  sim::SimulateScenario(scenario, options, root / "data");
  ReconstructJob job;
  job.dataset = root / "data";
  job.quiet = true;
  return job;
}

// ... and placed with the simulator's true poses.
inline ReconstructJob SimulatedJobOnTruePoses(const std::filesystem::path& root,
                                              const std::string& scenario,
                                              const sim::ScenarioOptions& options) {
  ReconstructJob job = SimulatedJob(root, scenario, options);
  job.poses_file = job.dataset / "groundtruth.tum";
  return job;
}

}  // namespace uwscan::pipeline_testing
