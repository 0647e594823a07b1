// `uwscan bench projection`: projections per second of each method on the
// thesis cameras Flat1-3, measured in one run so that ratios are meaningful.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace uwscan {

struct ProjectionBenchmarkOptions {
  int points = 200000;  // points per camera (random pixels at 0.5-10 m)
  int repetitions = 5;  // best of N
  unsigned seed = 1;
  void Check() const;
};

struct ProjectionRate {
  std::string camera;
  std::string method;  // pinhole, taylor1, taylor2, taylor3, exact, bounds
  double points_per_second = 0.0;
  double max_error_px = 0.0;  // against exact (0 for exact itself)
};

// Taylor projection error against exact over the full image (thesis
// Figs. 4.10-4.12 b, c) for one camera, depth, start and variant.
struct TaylorAccuracy {
  std::string camera;
  double depth_m = 0.0;
  std::string start;    // "paraxial" or "pinhole3m" (best pinhole fitted at 3 m, Tab. 4.6)
  std::string variant;  // "centred" or "thesis-axis"
  int iterations = 0;
  double start_max_px = 0.0;  // error of the start itself
  double max_px = 0.0;
  double median_px = 0.0;
};

std::vector<ProjectionRate> RunProjectionBenchmark(const ProjectionBenchmarkOptions& options);
// Grid every `step_px` over the 1280x960 image at 0.5, 1, 3 and 10 m.
std::vector<TaylorAccuracy> RunTaylorAccuracy(int step_px = 8);

nlohmann::json ProjectionBenchmarkToJson(const std::vector<ProjectionRate>& rates,
                                         const std::vector<TaylorAccuracy>& accuracy,
                                         const ProjectionBenchmarkOptions& options);
std::string ProjectionBenchmarkToMarkdown(const std::vector<ProjectionRate>& rates,
                                          const std::vector<TaylorAccuracy>& accuracy);

}  // namespace uwscan
