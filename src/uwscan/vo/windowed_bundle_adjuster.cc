#include "uwscan/vo/windowed_bundle_adjuster.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "uwscan/util/error.h"
#include "uwscan/util/stopwatch.h"
#include "uwscan/vo/cost_functions.h"

namespace uwscan::vo {

void BundleAdjustmentOptions::Check() const {
  UWS_CHECK(window_size >= 2, "window_size must be >= 2");
  UWS_CHECK(num_fixed_keyframes >= 1 && num_fixed_keyframes < window_size,
            "num_fixed_keyframes must be in [1, window_size)");
  UWS_CHECK(num_fixed_keyframes_with_ranges >= 1, "num_fixed_keyframes_with_ranges must be >= 1");
  UWS_CHECK(history_keyframes >= 0, "history_keyframes must be >= 0");
  UWS_CHECK(taylor_iterations >= 1, "taylor_iterations must be >= 1");
  UWS_CHECK(sigma_px > 0 && huber_px > 0 && outlier_px > 0, "sigma/huber/outlier must be > 0");
  UWS_CHECK(max_iterations >= 1, "max_iterations must be >= 1");
  UWS_CHECK(max_solver_time_s > 0 && std::isfinite(max_solver_time_s),
            "the BA time limit (--ba-time-limit) must be a positive number of seconds");
  UWS_CHECK(range_cauchy_sigmas > 0 && range_outlier_sigmas > 0,
            "range_cauchy_sigmas and range_outlier_sigmas must be > 0");
}

namespace {

struct PoseBlock {
  double q[4];
  double t[3];
};

}  // namespace

BundleAdjustmentSummary AdjustWindow(const Camera& camera, const BundleAdjustmentOptions& options,
                                     SparseMap* map, bool two_view_init) {
  options.Check();
  const auto start = std::chrono::steady_clock::now();
  BundleAdjustmentSummary summary;
  const int total = int(map->keyframes.size());
  const int first = std::max(0, total - options.window_size);
  const int count = total - first;
  if (count < 2) return summary;
  UWS_CHECK(!two_view_init || count == 2, "two-view adjustment needs exactly two keyframes");
  const CameraParams params(camera);

  std::vector<PoseBlock> poses(static_cast<size_t>(count));
  WindowParameters window;
  bool has_ranges = false;
  for (int k = 0; k < count; ++k) {
    Keyframe& kf = map->keyframes[size_t(first + k)];
    const Eigen::Quaterniond& q = kf.camera_from_world.rotation;
    poses[size_t(k)] = {{q.x(), q.y(), q.z(), q.w()},
                        {kf.camera_from_world.translation.x(), kf.camera_from_world.translation.y(),
                         kf.camera_from_world.translation.z()}};
    window.keyframes[kf.id] = {poses[size_t(k)].q, poses[size_t(k)].t};
    has_ranges = has_ranges || !kf.range_constraints.empty();
  }

  ceres::Problem::Options problem_options;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  ceres::EigenQuaternionManifold quaternion_manifold;
  ceres::SphereManifold<3> sphere_manifold;
  ceres::HuberLoss* loss = new ceres::HuberLoss(options.huber_px / options.sigma_px);

  struct ResidualRef {
    ceres::ResidualBlockId id;
    uint64_t point_id;
    int keyframe;
  };
  std::vector<ResidualRef> residual_refs, range_refs;
  // Shared by all range residuals; owned by the problem once one uses it.
  ceres::LossFunction* range_loss = new ceres::CauchyLoss(options.range_cauchy_sigmas);
  for (int k = 0; k < count; ++k) {
    Keyframe& kf = map->keyframes[size_t(first + k)];
    PoseBlock& pose = poses[size_t(k)];
    for (const auto& [point_id, pixel] : kf.observations) {
      auto it = map->points.find(point_id);
      if (it == map->points.end()) continue;
      double* point = it->second.position_world.data();
      window.points[point_id] = point;
      const ceres::ResidualBlockId id = problem.AddResidualBlock(
          ReprojectionCost::Create(params, options.method, options.taylor_iterations, pixel,
                                   options.sigma_px),
          loss, pose.q, pose.t, point);
      residual_refs.push_back({id, point_id, k});
    }
  }
  // Keyframes before the window, held: their rays of the window's points.
  const int history = two_view_init ? 0 : std::min(options.history_keyframes, first);
  std::vector<PoseBlock> held(static_cast<size_t>(history));
  std::vector<ResidualRef> history_refs;
  for (int h = 0; h < history; ++h) {
    Keyframe& kf = map->keyframes[size_t(first - history + h)];
    const Eigen::Quaterniond& q = kf.camera_from_world.rotation;
    PoseBlock& pose = held[size_t(h)];
    pose = {{q.x(), q.y(), q.z(), q.w()},
            {kf.camera_from_world.translation.x(), kf.camera_from_world.translation.y(),
             kf.camera_from_world.translation.z()}};
    for (const auto& [point_id, pixel] : kf.observations) {
      const auto it = window.points.find(point_id);
      if (it == window.points.end()) continue;
      const ceres::ResidualBlockId id = problem.AddResidualBlock(
          ReprojectionCost::Create(params, options.method, options.taylor_iterations, pixel,
                                   options.sigma_px),
          loss, pose.q, pose.t, it->second);
      history_refs.push_back({id, point_id, h - history});  // before the window
    }
    if (problem.HasParameterBlock(pose.q)) {
      problem.SetParameterBlockConstant(pose.q);
      problem.SetParameterBlockConstant(pose.t);
    }
  }
  // Range constraints only on points some keyframe of the window sees: a
  // range alone leaves a point free across its ray.
  for (int k = 0; k < count; ++k) {
    Keyframe& kf = map->keyframes[size_t(first + k)];
    PoseBlock& pose = poses[size_t(k)];
    for (const RangeConstraint& range : kf.range_constraints) {
      auto it = map->points.find(range.point_id);
      if (it == map->points.end() || !window.points.count(range.point_id)) continue;
      Eigen::Vector3d origin;
      if (range.ray_origin_camera) {
        origin = *range.ray_origin_camera;
      } else {
        auto obs = kf.observations.find(range.point_id);
        if (obs == kf.observations.end()) continue;
        const std::optional<Ray> ray = camera.BackProject(obs->second);
        if (!ray) continue;
        origin = ray->origin;
      }
      const ceres::ResidualBlockId id =
          problem.AddResidualBlock(RangeCost::Create(origin, range.range_m, range.sigma_m),
                                   range_loss, pose.q, pose.t, it->second.position_world.data());
      range_refs.push_back({id, range.point_id, k});
      ++summary.range_residuals;
    }
  }
  // The problem owns a loss only once a residual uses it.
  if (range_refs.empty()) delete range_loss;
  if (residual_refs.empty()) {
    delete loss;
    return summary;
  }
  const int fixed = two_view_init ? 1
                    : summary.range_residuals > 0
                        ? std::min(options.num_fixed_keyframes_with_ranges, count - 1)
                        : std::min(options.num_fixed_keyframes, count - 1);
  for (int k = 0; k < count; ++k) {
    PoseBlock& pose = poses[size_t(k)];
    if (!problem.HasParameterBlock(pose.q)) continue;
    problem.SetManifold(pose.q, &quaternion_manifold);
    if (k < fixed) {
      problem.SetParameterBlockConstant(pose.q);
      problem.SetParameterBlockConstant(pose.t);
    } else if (two_view_init) {
      problem.SetManifold(pose.t, &sphere_manifold);
    }
  }
  if (options.extra_residuals) options.extra_residuals(problem, window);

  auto rms = [&]() {
    double sum = 0;
    int n = 0;
    for (const ResidualRef& ref : residual_refs) {
      double residual[2];
      const auto* cost = problem.GetCostFunctionForResidualBlock(ref.id);
      std::vector<double*> blocks;
      problem.GetParameterBlocksForResidualBlock(ref.id, &blocks);
      if (!cost->Evaluate(blocks.data(), residual, nullptr)) continue;
      sum += residual[0] * residual[0] + residual[1] * residual[1];
      ++n;
    }
    return n > 0 ? std::sqrt(sum / n) * options.sigma_px : 0.0;
  };
  summary.initial_rms_px = rms();

  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::SPARSE_SCHUR;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.max_solver_time_in_seconds = options.max_solver_time_s;
  solver_options.num_threads = 1;
  solver_options.logging_type = ceres::SILENT;
  ceres::Solver::Summary ceres_summary;
  ceres::Solve(solver_options, &problem, &ceres_summary);
  summary.iterations = int(ceres_summary.iterations.size());
  summary.converged = ceres_summary.termination_type == ceres::CONVERGENCE;
  summary.time_limited = ceres_summary.termination_type == ceres::NO_CONVERGENCE &&
                         ceres_summary.total_time_in_seconds >= options.max_solver_time_s;
  summary.final_rms_px = rms();
  summary.keyframes = count;
  summary.points = int(window.points.size());
  summary.residuals = int(residual_refs.size());

  for (int k = 0; k < count; ++k) {
    Keyframe& kf = map->keyframes[size_t(first + k)];
    const PoseBlock& pose = poses[size_t(k)];
    kf.camera_from_world = Rigid3d(Eigen::Quaterniond(pose.q[3], pose.q[0], pose.q[1], pose.q[2]),
                                   Eigen::Vector3d(pose.t[0], pose.t[1], pose.t[2]));
  }
  // Outliers: drop observations whose re-projection error stays large.
  auto error_px = [&](ceres::ResidualBlockId id) {
    double residual[2];
    std::vector<double*> blocks;
    problem.GetParameterBlocksForResidualBlock(id, &blocks);
    const bool ok =
        problem.GetCostFunctionForResidualBlock(id)->Evaluate(blocks.data(), residual, nullptr);
    return ok ? std::hypot(residual[0], residual[1]) * options.sigma_px : 1e9;
  };
  for (const ResidualRef& ref : residual_refs) {
    if (error_px(ref.id) <= options.outlier_px) continue;
    Keyframe& kf = map->keyframes[size_t(first + ref.keyframe)];
    kf.observations.erase(ref.point_id);
    if (ref.keyframe == count - 1) summary.removed_observations.push_back(ref.point_id);
  }
  for (const ResidualRef& ref : history_refs) {
    if (error_px(ref.id) > options.outlier_px) {
      map->keyframes[size_t(first + ref.keyframe)].observations.erase(ref.point_id);
    }
  }
  // Range constraints that stay far off after the solve are wrong (§5.4).
  for (const ResidualRef& ref : range_refs) {
    double residual = 0.0;
    std::vector<double*> blocks;
    problem.GetParameterBlocksForResidualBlock(ref.id, &blocks);
    const bool ok = problem.GetCostFunctionForResidualBlock(ref.id)->Evaluate(blocks.data(),
                                                                              &residual, nullptr);
    if (ok && std::abs(residual) <= options.range_outlier_sigmas) continue;
    auto& ranges = map->keyframes[size_t(first + ref.keyframe)].range_constraints;
    ranges.erase(
        std::remove_if(ranges.begin(), ranges.end(),
                       [&](const RangeConstraint& r) { return r.point_id == ref.point_id; }),
        ranges.end());
    ++summary.removed_range_constraints;
  }
  summary.time_s = SecondsSince(start);
  return summary;
}

}  // namespace uwscan::vo
