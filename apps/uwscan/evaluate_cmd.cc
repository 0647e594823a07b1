// uwscan evaluate: a reconstruction against a simulated dataset's truth.
#include <cstdio>
#include <iostream>

#include "commands.h"
#include "uwscan/pipeline/evaluate_reconstruction.h"
#include "uwscan/util/atomic_file.h"

namespace uwscan::cli {

void RegisterEvaluateCommand(CLI::App& app) {
  auto dataset = std::make_shared<std::string>();
  auto result = std::make_shared<std::string>();
  auto json_path = std::make_shared<std::string>();
  auto* cmd = app.add_subcommand("evaluate", "Compare a reconstruction with the simulator's ground truth");
  cmd->add_option("--dataset", *dataset, "simulated dataset (scene.yaml, groundtruth.tum)")->required();
  cmd->add_option("--result", *result, "output folder of uwscan reconstruct")->required();
  cmd->add_option("--json", *json_path, "also write the evaluation as JSON here");
  cmd->callback([=] {
    const auto evaluation = EvaluateReconstruction(*dataset, *result);
    std::printf("%-16s %-12s %8s %12s %14s %12s\n", "cloud", "surface", "points", "fit std mm",
                "point err mm", "dist err %");
    for (const auto& [label, cloud] : {std::pair{"compensated", &evaluation.compensated},
                                       std::pair{"uncompensated", &evaluation.uncompensated}}) {
      std::printf("%-16s %-12s %8ld %12s %14.3f %12s\n", label, "(all)", cloud->matched, "",
                  cloud->point_error_rms_m * 1e3, "");
      for (const auto& s : cloud->surfaces) {
        if (s.points == 0) continue;
        std::printf("%-16s %-12s %8ld %12.3f %14.3f %12.3f\n", label, s.name.c_str(), s.points,
                    s.fit_rms_m * 1e3, s.point_error_rms_m * 1e3, s.distance_error_mean_pct);
      }
    }
    if (!json_path->empty()) WriteFileAtomic(*json_path, evaluation.ToJson().dump(2) + "\n");
  });
}

}  // namespace uwscan::cli
