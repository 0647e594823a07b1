// uwscan bench projection
#include <iostream>

#include "commands.h"
#include "uwscan/pipeline/projection_benchmark.h"
#include "uwscan/util/error.h"

namespace uwscan::cli {

void RegisterBenchCommands(CLI::App& app) {
  auto* bench = app.add_subcommand("bench", "Speed benchmarks, printed as JSON");
  bench->require_subcommand(1);
  auto options = std::make_shared<ProjectionBenchmarkOptions>();
  auto* projection = bench->add_subcommand(
      "projection", "Projections/s of pinhole, Taylor (1-3 iterations) and exact on Flat1-3");
  projection->add_option("--points", options->points, "points per camera")->capture_default_str();
  projection->add_option("--repetitions", options->repetitions, "best of N")->capture_default_str();
  auto markdown = std::make_shared<bool>(false);
  projection->add_flag("--markdown", *markdown, "print Markdown tables instead of JSON");
  projection->callback([options, markdown] {
    const auto rates = RunProjectionBenchmark(*options);
    const auto accuracy = RunTaylorAccuracy();
    if (*markdown) {
      std::cout << ProjectionBenchmarkToMarkdown(rates, accuracy);
    } else {
      std::cout << ProjectionBenchmarkToJson(rates, accuracy, *options).dump(2) << "\n";
    }
  });
}

}  // namespace uwscan::cli
