// uwscan evaluate --dataset DIR (--trajectory T.tum | --result OUT): a result
// against the dataset's ground truth: the trajectory (ATE after Sim(3), RPE,
// KITTI drift) and, for a reconstruction of a simulated dataset, its clouds
// (plane/cylinder fits, distance and point errors, compensated vs not).
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "commands.h"
#include "uwscan/eval/trajectory_metrics.h"
#include "uwscan/io/tum_trajectory.h"
#include "uwscan/pipeline/evaluate_reconstruction.h"
#include "uwscan/util/atomic_file.h"
#include "uwscan/util/error.h"

namespace uwscan::cli {
namespace {
namespace fs = std::filesystem;

// A figure, or blank where it was not measured.
std::string Figure(bool measured, const char* format, double value) {
  if (!measured) return "";
  char text[32];
  std::snprintf(text, sizeof(text), format, value);
  return text;
}

void PrintCloudEvaluation(const ReconstructionEvaluation& evaluation) {
  std::printf("%-16s %-12s %8s %12s %22s %14s %12s\n", "cloud", "surface", "points", "fit std mm",
              "robust fit mm (drop)", "point err mm", "dist err %");
  bool too_few = false;
  for (const auto& [label, cloud] : {std::pair{"compensated", &evaluation.compensated},
                                     std::pair{"uncompensated", &evaluation.uncompensated}}) {
    std::printf("%-16s %-12s %8ld %12s %22s %14s %12s\n", label, "(all)", cloud->matched, "", "",
                Figure(cloud->matched > 0, "%.3f", cloud->point_error_rms_m * 1e3).c_str(), "");
    for (const auto& s : cloud->surfaces) {
      if (s.points == 0) continue;
      too_few |= !s.Measured();
      std::string robust = Figure(s.robust_fitted, "%.3f", s.robust_fit_rms_m * 1e3);
      if (s.robust_fitted) robust += " (" + std::to_string(s.robust_outliers) + ")";
      std::printf("%-16s %-12s %8ld %12s %22s %14s %12s\n", label, s.name.c_str(), s.points,
                  Figure(s.fitted, "%.3f", s.fit_rms_m * 1e3).c_str(), robust.c_str(),
                  Figure(s.Measured(), "%.3f", s.point_error_rms_m * 1e3).c_str(),
                  Figure(s.distance_pairs > 0, "%.3f", s.distance_error_mean_pct).c_str());
    }
  }
  if (too_few) {
    std::printf("(a surface with fewer than %ld points is counted, not measured)\n",
                SurfaceAccuracy::kMinPoints);
  }
}

std::string FileText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// The dataset a result was reconstructed from, as its report.json names it,
// when that is another folder with another ground truth (evaluating a
// result against the wrong dataset gives figures that mean nothing, and
// nothing else tells: simulated scans share their timestamps). Empty
// otherwise, also when the folder is gone or was copied (same truth).
std::string OtherDatasetOfResult(const fs::path& result, const fs::path& dataset) {
  std::ifstream in(result / "report.json");
  const nlohmann::json report = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (!report.is_object() || !report.contains("dataset") || !report["dataset"].is_string()) {
    return "";
  }
  const fs::path made_from = report["dataset"].get<std::string>();
  std::error_code error;
  if (!fs::exists(made_from / "groundtruth.tum", error) ||
      fs::equivalent(made_from, dataset, error)) {
    return "";
  }
  return FileText(made_from / "groundtruth.tum") == FileText(dataset / "groundtruth.tum")
             ? ""
             : made_from.string();
}

}  // namespace

void RegisterEvaluateCommand(CLI::App& app) {
  auto* evaluate = app.add_subcommand(
      "evaluate", "Compare a result with the dataset's ground truth (trajectory and clouds)");
  auto dataset = std::make_shared<std::string>();
  auto trajectory = std::make_shared<std::string>();
  auto result = std::make_shared<std::string>();
  auto json_path = std::make_shared<std::string>();
  auto options = std::make_shared<TrajectoryMetricsOptions>();
  auto se3 = std::make_shared<bool>(false);
  evaluate->add_option("--dataset", *dataset, "dataset folder with groundtruth.tum")->required();
  evaluate->add_option("--trajectory", *trajectory, "estimated trajectory (TUM)");
  evaluate->add_option(
      "--result", *result,
      "output folder of reconstruct (trajectory.tum, cloud.ply, cloud_uncompensated.ply)");
  evaluate->add_option("--json", *json_path,
                       "also write the figures as JSON here (trajectory; clouds with --result)");
  evaluate->add_option("--lengths", options->drift_lengths_m,
                       "drift path lengths in m (default: 10..50 % of the path)");
  auto* rpe_step_given = evaluate->add_option(
      "--rpe-step", options->rpe_step,
      "RPE between poses this many ground-truth frames apart (default: the estimate's own step, "
      "1 for a pose every frame)");
  evaluate
      ->add_option("--max-dt", options->max_time_difference_s,
                   "timestamp association tolerance (s)")
      ->capture_default_str();
  evaluate->add_option("--rpe-from", options->rpe_from_s, "RPE only from this time (s)");
  evaluate->add_option("--rpe-to", options->rpe_to_s, "RPE only up to this time (s)");
  evaluate->add_flag("--se3", *se3, "align without scale (metric trajectories)");
  auto viewed_depth = std::make_shared<double>(-1.0);
  auto* viewed_depth_given =
      evaluate->add_option("--viewed-depth", *viewed_depth,
                           "distance to the scene along the optical axis (m) for the motion of "
                           "what the camera looks at (default: from the dataset's scene; 0: off)");
  evaluate->callback([=] {
    if (trajectory->empty() == result->empty()) {
      throw UsageError("evaluate needs exactly one of --trajectory and --result");
    }
    const fs::path estimate_path =
        trajectory->empty() ? fs::path(*result) / "trajectory.tum" : fs::path(*trajectory);
    const fs::path truth_path = fs::path(*dataset) / "groundtruth.tum";
    UWS_CHECK(fs::exists(truth_path), truth_path.string(), ": no ground truth");
    options->align_scale = !*se3;
    for (double length : options->drift_lengths_m) {
      UWS_USAGE_CHECK(length > 0, "--lengths must be path lengths > 0 (m), got ", length);
    }
    UWS_USAGE_CHECK(rpe_step_given->count() == 0 || options->rpe_step >= 1,
                    "--rpe-step must be >= 1, got ", options->rpe_step);
    UWS_USAGE_CHECK(options->max_time_difference_s >= 0,
                    "--max-dt must be a time difference >= 0 (s), got ",
                    options->max_time_difference_s);
    UWS_USAGE_CHECK(!std::isnan(options->rpe_from_s) && !std::isnan(options->rpe_to_s),
                    "--rpe-from and --rpe-to must be times (s)");
    UWS_USAGE_CHECK(options->rpe_from_s <= options->rpe_to_s, "--rpe-from (", options->rpe_from_s,
                    " s) is after --rpe-to (", options->rpe_to_s, " s)");
    UWS_USAGE_CHECK(
        viewed_depth_given->count() == 0 || (*viewed_depth >= 0 && std::isfinite(*viewed_depth)),
        "--viewed-depth must be a distance >= 0 (m), got ", *viewed_depth);
    options->viewed_depth_m =
        viewed_depth_given->count() > 0 ? *viewed_depth : MedianViewedDepth(*dataset);
    // A reconstruction's clouds are compared with a simulated dataset's
    // scene; both must be there before anything is printed.
    UWS_CHECK(result->empty() || fs::is_directory(*result), *result,
              ": no such folder (--result is the output folder of reconstruct)");
    const bool with_clouds = !result->empty() && fs::exists(fs::path(*dataset) / "scene.yaml");
    for (const char* cloud : {"cloud.ply", "cloud_uncompensated.ply"}) {
      UWS_CHECK(!with_clouds || fs::exists(fs::path(*result) / cloud),
                (fs::path(*result) / cloud).string(),
                ": missing (reconstruct writes it beside trajectory.tum)");
    }
    if (!json_path->empty()) {
      RefuseOutputOntoInput("--json", *json_path,
                            {estimate_path, truth_path, fs::path(*dataset) / "scene.yaml"});
    }
    if (!result->empty()) {
      const std::string made_from = OtherDatasetOfResult(*result, *dataset);
      if (!made_from.empty()) {
        std::fprintf(stderr,
                     "uwscan: warning: %s was reconstructed from %s (its report.json), whose "
                     "ground truth is not %s's: these figures compare two different scans\n",
                     result->c_str(), made_from.c_str(), dataset->c_str());
      }
    }
    const TumTrajectory estimate = ReadTumTrajectory(estimate_path);
    const TumTrajectory truth = ReadTumTrajectory(truth_path);
    TrajectoryMetrics metrics;
    try {
      metrics = ComputeTrajectoryMetrics(estimate.poses, truth.poses, *options);
    } catch (const Error& e) {  // e.g. too few poses: say which files
      UWS_THROW(estimate_path.string(), " against ", truth_path.string(), ": ", e.what());
    }
    std::printf("trajectory %s vs %s (%zu gaps marked)\n%s", estimate_path.c_str(),
                truth_path.c_str(), estimate.gaps.size(), FormatTrajectoryMetrics(metrics).c_str());
    nlohmann::json json = {{"trajectory", metrics.ToJson()}};
    json["trajectory"]["estimate"] = estimate_path.string();
    json["trajectory"]["ground_truth"] = truth_path.string();
    json["trajectory"]["gaps_marked"] = estimate.gaps.size();
    if (with_clouds) {
      const auto evaluation = EvaluateReconstruction(*dataset, *result);
      PrintCloudEvaluation(evaluation);
      json.update(evaluation.ToJson());  // "compensated", "uncompensated"
    } else if (!result->empty()) {
      std::printf("clouds: not evaluated (%s has no scene.yaml, the simulator's true scene)\n",
                  dataset->c_str());
    }
    if (!json_path->empty()) WriteFileAtomic(*json_path, json.dump(2) + "\n");
  });
}

}  // namespace uwscan::cli
