// uwscan evaluate --dataset DIR (--trajectory T.tum | --result OUT): trajectory
// accuracy against DIR/groundtruth.tum (ATE after Sim(3), RPE, KITTI drift).
#include <cstdio>
#include <filesystem>

#include "commands.h"
#include "uwscan/eval/trajectory_metrics.h"
#include "uwscan/io/tum_trajectory.h"
#include "uwscan/util/error.h"

namespace uwscan::cli {

void RegisterEvaluateCommand(CLI::App& app) {
  auto* evaluate = app.add_subcommand(
      "evaluate", "Compare a result with the dataset's ground truth (trajectory: ATE, RPE, drift)");
  auto dataset = std::make_shared<std::string>();
  auto trajectory = std::make_shared<std::string>();
  auto result = std::make_shared<std::string>();
  auto options = std::make_shared<TrajectoryMetricsOptions>();
  auto se3 = std::make_shared<bool>(false);
  evaluate->add_option("--dataset", *dataset, "dataset folder with groundtruth.tum")->required();
  evaluate->add_option("--trajectory", *trajectory, "estimated trajectory (TUM)");
  evaluate->add_option("--result", *result, "result folder of reconstruct (uses trajectory.tum)");
  evaluate->add_option("--lengths", options->drift_lengths_m,
                       "drift path lengths in m (default: 10..50 % of the path)");
  evaluate->add_option("--rpe-step", options->rpe_step, "RPE frame step")->capture_default_str();
  evaluate
      ->add_option("--max-dt", options->max_time_difference_s,
                   "timestamp association tolerance (s)")
      ->capture_default_str();
  evaluate->add_option("--rpe-from", options->rpe_from_s, "RPE only from this time (s)");
  evaluate->add_option("--rpe-to", options->rpe_to_s, "RPE only up to this time (s)");
  evaluate->add_flag("--se3", *se3, "align without scale (metric trajectories)");
  evaluate->callback([=] {
    if (trajectory->empty() == result->empty()) {
      throw UsageError("evaluate needs exactly one of --trajectory and --result");
    }
    const std::filesystem::path estimate_path =
        trajectory->empty() ? std::filesystem::path(*result) / "trajectory.tum"
                            : std::filesystem::path(*trajectory);
    const std::filesystem::path truth_path = std::filesystem::path(*dataset) / "groundtruth.tum";
    UWS_CHECK(std::filesystem::exists(truth_path), truth_path.string(), ": no ground truth");
    options->align_scale = !*se3;
    const TumTrajectory estimate = ReadTumTrajectory(estimate_path);
    const TumTrajectory truth = ReadTumTrajectory(truth_path);
    const TrajectoryMetrics metrics =
        ComputeTrajectoryMetrics(estimate.poses, truth.poses, *options);
    std::printf("trajectory %s vs %s (%zu gaps marked)\n%s", estimate_path.c_str(),
                truth_path.c_str(), estimate.gaps.size(), FormatTrajectoryMetrics(metrics).c_str());
  });
}

}  // namespace uwscan::cli
