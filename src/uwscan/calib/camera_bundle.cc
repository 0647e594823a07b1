#include "uwscan/calib/camera_bundle.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "uwscan/util/error.h"

namespace uwscan {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct PoseBlock {
  std::array<double, 4> q;  // w x y z
  std::array<double, 3> t;
};

PoseBlock ToBlock(const Rigid3d& pose) {
  const Eigen::Quaterniond& r = pose.rotation;
  return {{r.w(), r.x(), r.y(), r.z()},
          {pose.translation.x(), pose.translation.y(), pose.translation.z()}};
}

Rigid3d FromBlock(const PoseBlock& block) {
  return Rigid3d(Eigen::Quaterniond(block.q[0], block.q[1], block.q[2], block.q[3]),
                 Eigen::Vector3d(block.t[0], block.t[1], block.t[2]));
}

// Camera parameters as Ceres blocks.
struct CameraBlocks {
  std::array<double, 4> intrinsics;
  std::array<double, 5> distortion;
  std::array<double, 3> normal;
  std::array<double, 1> d_air;
  std::array<double, 4> media;  // d_glass n_air n_glass n_water

  explicit CameraBlocks(const Camera& camera) {
    intrinsics = camera.intrinsics;
    distortion = camera.distortion;
    const Eigen::Vector3d n = camera.port.normal.normalized();
    normal = {n.x(), n.y(), n.z()};
    d_air = {camera.port.d_air};
    media = {camera.port.d_glass, camera.port.n_air, camera.port.n_glass, camera.port.n_water};
  }
  void CopyTo(Camera* camera) const {
    camera->intrinsics = intrinsics;
    camera->distortion = distortion;
    camera->port.normal = Eigen::Vector3d(normal[0], normal[1], normal[2]).normalized();
    camera->port.d_air = d_air[0];
    camera->port.n_water = media[3];
  }
};

}  // namespace

void CameraBundleOptions::Check() const {
  UWS_CHECK(max_iterations > 0, "max_iterations must be positive");
  UWS_CHECK(taylor_iterations >= 1 && taylor_iterations <= 10,
            "taylor_iterations must be in [1, 10]");
}

std::vector<Eigen::Vector2d> ViewResiduals(const Camera& camera, const BoardSpec& board,
                                           const ViewCorners& view,
                                           const Rigid3d& camera_from_board,
                                           std::vector<bool>* valid) {
  const std::vector<Eigen::Vector3d> points = board.Corners();
  std::vector<Eigen::Vector2d> residuals(points.size(), Eigen::Vector2d::Zero());
  valid->assign(points.size(), false);
  for (size_t i = 0; i < points.size(); ++i) {
    const auto pixel = camera.Project(camera_from_board * points[i], ProjectionMethod::kExact);
    if (!pixel) continue;
    residuals[i] = *pixel - view.corners[i];
    (*valid)[i] = true;
  }
  return residuals;
}

CameraBundleResult SolveCameraBundle(const CornerSet& set, const std::vector<bool>& use_view,
                                     const CameraBundleOptions& options, Camera* camera,
                                     std::vector<Rigid3d>* camera_from_board) {
  options.Check();
  UWS_CHECK(use_view.size() == set.views.size() && camera_from_board->size() == set.views.size(),
            "SolveCameraBundle: one flag and one pose per view expected");
  const bool flat = camera->IsFlatPort();
  const CameraParameterMask& free = options.free;
  CameraBlocks blocks(*camera);
  std::vector<PoseBlock> poses;
  for (const Rigid3d& pose : *camera_from_board) poses.push_back(ToBlock(pose));
  const std::vector<Eigen::Vector3d> points = set.board.Corners();

  std::array<double, 4> air_media = {blocks.media[0], blocks.media[1], blocks.media[2],
                                     blocks.media[1]};
  // Without a port: air on every side of a glass of air, so rays go straight.
  std::array<double, 4> portless_media = {blocks.media[0], blocks.media[1], blocks.media[1],
                                          blocks.media[1]};
  UWS_CHECK(options.view_in_air.empty() || options.view_in_air.size() == set.views.size(),
            "SolveCameraBundle: view_in_air needs one flag per view");
  UWS_CHECK(options.view_without_port.empty() || options.view_without_port.size() == set.views.size(),
            "SolveCameraBundle: view_without_port needs one flag per view");
  auto in_air = [&](size_t v) { return !options.view_in_air.empty() && options.view_in_air[v]; };
  auto portless = [&](size_t v) {
    return !options.view_without_port.empty() && options.view_without_port[v];
  };
  auto media_of = [&](size_t v) {
    return portless(v) ? portless_media.data() : in_air(v) ? air_media.data() : blocks.media.data();
  };

  ceres::Problem problem;
  int used_views = 0, residual_count = 0;
  for (size_t v = 0; v < set.views.size(); ++v) {
    if (!use_view[v]) continue;
    ++used_views;
    for (size_t i = 0; i < points.size(); ++i) {
      const Eigen::Vector2d& observed = set.views[v].corners[i];
      if (flat) {
        problem.AddResidualBlock(
            FlatPortReprojectionCost::Create(observed, points[i], options.residual,
                                             options.taylor_iterations),
            nullptr, blocks.intrinsics.data(), blocks.distortion.data(), blocks.normal.data(),
            blocks.d_air.data(), media_of(v), poses[v].q.data(), poses[v].t.data());
      } else {
        problem.AddResidualBlock(PinholeReprojectionCost::Create(observed, points[i]), nullptr,
                                 blocks.intrinsics.data(), blocks.distortion.data(),
                                 poses[v].q.data(), poses[v].t.data());
      }
      ++residual_count;
    }
    problem.SetManifold(poses[v].q.data(), new ceres::QuaternionManifold);
    if (!free.poses) {
      problem.SetParameterBlockConstant(poses[v].q.data());
      problem.SetParameterBlockConstant(poses[v].t.data());
    }
  }
  UWS_CHECK(used_views > 0, "calibration: no view left to solve with");

  int free_parameters = 0;
  if (free.intrinsics) {
    free_parameters += 4;
  } else {
    problem.SetParameterBlockConstant(blocks.intrinsics.data());
  }
  if (free.distortion) {
    free_parameters += free.fix_k3 ? 4 : 5;
    if (free.fix_k3)
      problem.SetManifold(blocks.distortion.data(), new ceres::SubsetManifold(5, {4}));
  } else {
    problem.SetParameterBlockConstant(blocks.distortion.data());
  }
  for (double* media : {air_media.data(), portless_media.data()}) {
    if (flat && problem.HasParameterBlock(media)) problem.SetParameterBlockConstant(media);
  }
  if (flat) {
    problem.SetManifold(blocks.normal.data(), new ceres::SphereManifold<3>);
    if (free.normal) {
      free_parameters += 2;
    } else {
      problem.SetParameterBlockConstant(blocks.normal.data());
    }
    if (free.d_air) {
      free_parameters += 1;
      problem.SetParameterLowerBound(blocks.d_air.data(), 0, 0.0);
    } else {
      problem.SetParameterBlockConstant(blocks.d_air.data());
    }
    if (free.n_water && problem.HasParameterBlock(blocks.media.data())) {
      free_parameters += 1;
      problem.SetManifold(blocks.media.data(), new ceres::SubsetManifold(4, {0, 1, 2}));
      problem.SetParameterLowerBound(blocks.media.data(), 3, 1.0);
    } else if (problem.HasParameterBlock(blocks.media.data())) {
      problem.SetParameterBlockConstant(blocks.media.data());
    }
  }
  if (free.poses) free_parameters += 6 * used_views;

  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::SPARSE_SCHUR;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.function_tolerance = 1e-12;
  solver_options.gradient_tolerance = 1e-14;
  solver_options.parameter_tolerance = 1e-12;
  solver_options.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  UWS_CHECK(summary.IsSolutionUsable(), "calibration: the solver failed: ", summary.message);

  CameraBundleResult result;
  result.converged = summary.termination_type == ceres::CONVERGENCE;
  result.iterations = static_cast<int>(summary.iterations.size()) - 1;
  blocks.CopyTo(camera);
  for (size_t v = 0; v < poses.size(); ++v) (*camera_from_board)[v] = FromBlock(poses[v]);

  // Residual statistics with the exact model, whatever the solver used.
  double sum_sq = 0.0;
  int count = 0;
  result.view_rms_px.assign(set.views.size(), kNaN);
  for (size_t v = 0; v < set.views.size(); ++v) {
    std::vector<bool> valid;
    Camera view_camera = *camera;
    if (flat && (in_air(v) || portless(v))) view_camera.port.n_water = view_camera.port.n_air;
    if (flat && portless(v)) view_camera.port.n_glass = view_camera.port.n_air;
    const auto residuals =
        ViewResiduals(view_camera, set.board, set.views[v], (*camera_from_board)[v], &valid);
    double view_sq = 0.0;
    bool all_valid = true;
    for (size_t i = 0; i < residuals.size(); ++i) {
      all_valid &= valid[i];
      if (!valid[i]) continue;
      view_sq += residuals[i].squaredNorm();
      if (use_view[v]) {
        const Eigen::Vector2d& c = set.views[v].corners[i];
        result.residuals.push_back(
            {static_cast<int>(v), c.x(), c.y(), residuals[i].x(), residuals[i].y()});
      }
    }
    if (all_valid) result.view_rms_px[v] = std::sqrt(view_sq / residuals.size());
    if (use_view[v]) {
      sum_sq += view_sq;
      count += static_cast<int>(residuals.size());
    }
  }
  result.rms_px = std::sqrt(sum_sq / std::max(count, 1));

  // Parameter standard deviations: Ceres covariance (unit-variance residuals)
  // scaled by the a-posteriori variance of one residual component.
  auto add = [&](const char* name, const double* value, double std_dev) {
    result.parameters.push_back({name, *value, std_dev});
  };
  const char* intrinsic_names[4] = {"fx", "fy", "cx", "cy"};
  const char* distortion_names[5] = {"k1", "k2", "p1", "p2", "k3"};
  const char* normal_names[3] = {"normal_x", "normal_y", "normal_z"};
  std::vector<const double*> covariance_blocks;
  if (free.intrinsics) covariance_blocks.push_back(blocks.intrinsics.data());
  if (free.distortion) covariance_blocks.push_back(blocks.distortion.data());
  if (flat && free.normal) covariance_blocks.push_back(blocks.normal.data());
  if (flat && free.d_air) covariance_blocks.push_back(blocks.d_air.data());
  if (flat && free.n_water && problem.HasParameterBlock(blocks.media.data()))
    covariance_blocks.push_back(blocks.media.data());
  std::vector<std::vector<double>> std_devs;
  const int redundancy = 2 * residual_count - free_parameters;
  if (options.compute_covariance && !covariance_blocks.empty() && redundancy > 0) {
    ceres::Covariance::Options covariance_options;
    covariance_options.algorithm_type = ceres::DENSE_SVD;
    covariance_options.null_space_rank = -1;
    covariance_options.min_reciprocal_condition_number = 1e-14;
    ceres::Covariance covariance(covariance_options);
    std::vector<std::pair<const double*, const double*>> pairs;
    for (const double* block : covariance_blocks) pairs.emplace_back(block, block);
    if (covariance.Compute(pairs, &problem)) {
      const double variance = 2.0 * summary.final_cost / redundancy;
      result.covariance_ok = true;
      for (const double* block : covariance_blocks) {
        const int size = problem.ParameterBlockSize(block);
        std::vector<double> matrix(size * size);
        covariance.GetCovarianceBlock(block, block, matrix.data());
        std::vector<double> stds(size);
        for (int i = 0; i < size; ++i)
          stds[i] = std::sqrt(std::max(0.0, matrix[i * size + i]) * variance);
        std_devs.push_back(stds);
      }
    }
  }
  size_t next = 0;
  auto std_of = [&](bool is_free, int index) {
    if (!is_free || !result.covariance_ok) return kNaN;
    return std_devs[next][index];
  };
  if (free.intrinsics) {
    for (int i = 0; i < 4; ++i) add(intrinsic_names[i], &blocks.intrinsics[i], std_of(true, i));
    next += result.covariance_ok;
  }
  if (free.distortion) {
    for (int i = 0; i < 5; ++i) {
      add(distortion_names[i], &blocks.distortion[i], std_of(!(free.fix_k3 && i == 4), i));
    }
    next += result.covariance_ok;
  }
  if (flat && free.normal) {
    for (int i = 0; i < 3; ++i) add(normal_names[i], &blocks.normal[i], std_of(true, i));
    // Tilt std: the normal's tangential spread, in degrees.
    const double tilt_deg = camera->port.TiltRad() * 180.0 / M_PI;
    double tilt_std = kNaN;
    if (result.covariance_ok) {
      const double sx = std_devs[next][0], sy = std_devs[next][1];
      tilt_std = std::hypot(sx, sy) / std::sqrt(2.0) * 180.0 / M_PI;
    }
    add("tilt_deg", &tilt_deg, tilt_std);
    next += result.covariance_ok;
  }
  if (flat && free.d_air) {
    add("d_air", &blocks.d_air[0], std_of(true, 0));
    next += result.covariance_ok;
  }
  if (flat && free.n_water && problem.HasParameterBlock(blocks.media.data()))
    add("n_water", &blocks.media[3], std_of(true, 3));
  return result;
}

}  // namespace uwscan
