// uwscan: underwater optical 3D scanning. Exit status: 0 success, 2 usage
// error, 1 bad input or runtime failure ("uwscan: error: ..." on stderr),
// 130 (143) interrupted by Ctrl-C (SIGTERM).
#include <glog/logging.h>
#include <malloc.h>

#include <iostream>

#include "commands.h"
#include "uwscan/util/error.h"
#include "uwscan/util/interrupt.h"

namespace {

// An empty value ("--out ''", an unset shell variable) is refused as a usage
// error naming the option, for every option of every command that takes one,
// before any command runs (it would otherwise reach a file name as "").
void RefuseEmptyValues(CLI::App* app) {
  const CLI::Validator not_empty(
      [](std::string& value) { return value.empty() ? std::string("empty value") : ""; }, "");
  for (CLI::Option* option : app->get_options()) {
    if (option->get_type_size() > 0) option->check(not_empty);
  }
  for (CLI::App* command : app->get_subcommands({})) RefuseEmptyValues(command);
}

// OpenCV's checkerboard detector and the simulator allocate and free
// buffers of several megabytes per image. glibc maps each afresh and returns
// it at once, and the kernel zero-fills its pages on every use: that took
// over a third of a calibration's time and a seventh of a simulation's
// (docs/BENCHMARKS.md). Taken from the heap and kept there, they are reused;
// each command's peak memory stays the same (the demo's, which simulates
// and then reconstructs in one process, goes from 198 to 253 MB).
void ReuseLargeBuffers() {
  mallopt(M_MMAP_THRESHOLD, 32 << 20);  // glibc's largest
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
}

}  // namespace

int main(int argc, char** argv) {
  ReuseLargeBuffers();
  // Ceres logs a solver's routine recoveries (a Levenberg-Marquardt step the
  // linear solver refused, retried with more damping) as glog warnings, and
  // a solve it gave up as an error; uwscan reads every solver's summary and
  // says what failed in its own words (a single `uwscan: error:` line), so
  // only glog's fatal messages reach stderr, and no log files are written.
  FLAGS_logtostderr = true;
  FLAGS_minloglevel = google::GLOG_FATAL;
  google::InitGoogleLogging(argv[0]);
  CLI::App app{"uwscan: underwater optical 3D scanning with flat-port cameras and line lasers"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "uwscan 0.1.0");
  uwscan::cli::RegisterCameraCommands(app);
  uwscan::cli::RegisterAnalyzeCommands(app);
  uwscan::cli::RegisterBenchCommands(app);
  uwscan::cli::RegisterDemoCommand(app);
  uwscan::cli::RegisterLaserCommands(app);
  uwscan::cli::RegisterSimulateCommand(app);
  uwscan::cli::RegisterReconstructCommand(app);
  uwscan::cli::RegisterEvaluateCommand(app);
  uwscan::cli::RegisterCalibrateCommands(app);
  uwscan::cli::RegisterVoCommand(app);
  RefuseEmptyValues(&app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  } catch (const uwscan::Interrupted& e) {
    std::cerr << "\nuwscan: " << e.what() << "\n";
    return 128 + e.signal();
  } catch (const uwscan::UsageError& e) {
    std::cerr << "uwscan: usage error: " << e.what() << "\n";
    return 2;
  } catch (const uwscan::Error& e) {
    std::cerr << "uwscan: error: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "uwscan: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
