// Each subcommand registers itself on the CLI11 app; its callback parses
// nothing more, checks paths and calls library code.
#pragma once

#include <CLI/CLI.hpp>

namespace uwscan::cli {

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
