// Simulated scans for the pipeline's tests: each test simulates what it
// needs into a temporary folder of its own and reconstructs it.
#pragma once

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "uwscan/io/dataset.h"
#include "uwscan/io/tum.h"
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

// Whether one of the report's warnings holds every one of `parts`.
inline bool Warns(const ReconstructReport& report, std::initializer_list<std::string_view> parts) {
  const std::vector<std::string> warnings = report.Warnings();
  return std::any_of(warnings.begin(), warnings.end(), [&](const std::string& warning) {
    return std::all_of(parts.begin(), parts.end(), [&](std::string_view part) {
      return warning.find(part) != std::string::npos;
    });
  });
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

// A copy of `dataset` at `to` whose clock runs `factor` times as slow
// (below 1: fast): the times of frames.csv, of every further camera's
// (DATASET/NAME/frames.csv) and of groundtruth.tum stretched from the
// first frame's. A live replay of it takes `factor` times the scan's time.
inline void CopyWithClockStretched(const std::filesystem::path& dataset,
                                   const std::filesystem::path& to, double factor) {
  namespace fs = std::filesystem;
  fs::copy(dataset, to, fs::copy_options::recursive);
  const double t0 = ReadFramesCsv(dataset / "frames.csv").front().timestamp_s;
  const auto stretched = [t0, factor](double t) { return t0 + factor * (t - t0); };
  std::vector<fs::path> folders = {fs::path()};
  for (const auto& entry : fs::directory_iterator(dataset)) {
    if (entry.is_directory() && fs::exists(entry.path() / "frames.csv"))
      folders.push_back(entry.path().filename());
  }
  for (const fs::path& folder : folders) {
    std::vector<FrameRecord> records = ReadFramesCsv(dataset / folder / "frames.csv");
    bool with_angle = false, with_on = false;
    for (const FrameRecord& record : records) {
      with_angle = with_angle || record.laser_angle_rad.has_value();
      with_on = with_on || record.laser_on.has_value();
    }
    FramesCsvWriter out(to / folder / "frames.csv", with_angle, with_on);
    for (FrameRecord& record : records) {
      record.timestamp_s = stretched(record.timestamp_s);
      out.Add(record);
    }
    out.Commit();
  }
  std::vector<StampedPose> truth = ReadTum(dataset / "groundtruth.tum");
  for (StampedPose& pose : truth) pose.timestamp_s = stretched(pose.timestamp_s);
  WriteTum(to / "groundtruth.tum", truth);
}

// RunReconstruct(job), doing `act` on another thread once the run's first
// outputs are committed (its report.json, written last, is there): a later
// run (another pass, the run on half the image) then meets what `act` did.
// `acted` (if given) says whether it came to that.
template <typename Act>
ReconstructReport RunReconstructActingOnceCommitted(const ReconstructJob& job, Act act,
                                                    bool* acted = nullptr) {
  std::atomic<bool> done = false, did = false;
  std::thread actor([&] {
    while (!done && !std::filesystem::exists(job.out / "report.json"))
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    if (done) return;
    act();
    did = true;
  });
  const auto finish = [&] {
    done = true;
    actor.join();
    if (acted) *acted = did;
  };
  try {
    ReconstructReport report = RunReconstruct(job);
    finish();
    return report;
  } catch (...) {
    finish();
    throw;
  }
}

}  // namespace uwscan::pipeline_testing
