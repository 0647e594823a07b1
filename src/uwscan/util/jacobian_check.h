// Test helper: compares a cost function's Jacobians (Ceres Jets) with
// numeric differentiation via ceres::GradientChecker.
#pragma once

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace uwscan {

// Returns an empty string when every Jacobian entry agrees with numeric
// differentiation within |a - n| <= precision * max(|a|, |n|) + absolute
// (the absolute floor only forgives round-off on entries that are zero), else
// a description of the worst entry.
inline std::string CheckJacobians(const ceres::CostFunction& cost,
                                  const std::vector<const double*>& parameters, double precision,
                                  double absolute = 1e-11) {
  ceres::NumericDiffOptions numeric_options;
  // GradientChecker uses Ridders extrapolation; its default first step (tens
  // of percent) leaves the domain of the models (e.g. invertible distortion).
  numeric_options.ridders_relative_initial_step_size = 1e-4;
  const std::vector<const ceres::Manifold*>* no_manifolds = nullptr;
  ceres::GradientChecker checker(&cost, no_manifolds, numeric_options);
  ceres::GradientChecker::ProbeResults results;
  checker.Probe(parameters.data(), precision, &results);
  if (results.jacobians.size() != parameters.size()) {
    return results.error_log.empty() ? "evaluation failed" : results.error_log;
  }
  std::string worst;
  double worst_excess = 0.0;
  for (size_t block = 0; block < results.jacobians.size(); ++block) {
    const auto& analytic = results.jacobians[block];
    const auto& numeric = results.numeric_jacobians[block];
    for (int r = 0; r < analytic.rows(); ++r) {
      for (int c = 0; c < analytic.cols(); ++c) {
        const double a = analytic(r, c), n = numeric(r, c);
        const double allowed = precision * std::max(std::abs(a), std::abs(n)) + absolute;
        const double excess = std::abs(a - n) / allowed;
        if (!(excess <= 1.0) && !(excess <= worst_excess)) {
          worst_excess = excess;
          worst = "block " + std::to_string(block) + " (" + std::to_string(r) + "," +
                  std::to_string(c) + "): jet " + std::to_string(a) + " numeric " +
                  std::to_string(n);
        }
      }
    }
  }
  return worst;
}

}  // namespace uwscan
