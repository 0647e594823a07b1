// Each subcommand registers itself on the CLI11 app; its callback parses
// nothing more, checks paths and calls library code.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>

namespace uwscan::cli {

// `--async-ba` and `--no-async-ba`, which exclude each other: `async` is
// set to true or false when one is given and left unset (the command's
// auto) otherwise. It must outlive the parse.
inline void AddAsyncBundleAdjustmentFlags(CLI::App* cmd, std::optional<bool>* async,
                                          const std::string& on_help) {
  CLI::Option* on = cmd->add_flag_callback(
      "--async-ba", [async] { *async = true; }, on_help);
  CLI::Option* off = cmd->add_flag_callback(
      "--no-async-ba", [async] { *async = false; },
      "the windowed BA on the tracking thread, each keyframe's result used at once");
  on->excludes(off);
}

// `--sample-bits N` (ScaleLowBitSamples), the same for every command that
// reads a camera's frames.
inline void AddSampleBitsOption(CLI::App* cmd, int* sample_bits) {
  cmd->add_option("--sample-bits", *sample_bits,
                  "16-bit frames hold samples of N bits in their low bits (a 10- or 12-bit "
                  "camera's frames saved unpacked): scaled up to the 16-bit range (16 = as "
                  "stored)")
      ->capture_default_str();
}

void RegisterCameraCommands(CLI::App& app);
void RegisterAnalyzeCommands(CLI::App& app);
void RegisterBenchCommands(CLI::App& app);
void RegisterDemoCommand(CLI::App& app);
void RegisterLaserCommands(CLI::App& app);
void RegisterSimulateCommand(CLI::App& app);
void RegisterReconstructCommand(CLI::App& app);
void RegisterEvaluateCommand(CLI::App& app);
void RegisterCalibrateCommands(CLI::App& app);
void RegisterVoCommand(CLI::App& app);

}  // namespace uwscan::cli
