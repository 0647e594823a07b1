// `uwscan bench projection`: projections per second of each method on the
// thesis cameras Flat1-3, measured in one run so that ratios are meaningful.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace uwscan {

struct ProjectionBenchmarkOptions {
  int points = 200000;   // points per camera (random pixels at 0.5-10 m)
  int repetitions = 5;   // best of N
  unsigned seed = 1;
  void Check() const;
};

struct ProjectionRate {
  std::string camera;
  std::string method;  // pinhole, taylor1, taylor2, taylor3, exact
  double points_per_second = 0.0;
  double max_error_px = 0.0;  // against exact (0 for exact itself)
};

std::vector<ProjectionRate> RunProjectionBenchmark(const ProjectionBenchmarkOptions& options);
nlohmann::json ProjectionBenchmarkToJson(const std::vector<ProjectionRate>& rates,
                                         const ProjectionBenchmarkOptions& options);

}  // namespace uwscan
