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
