#include "uwscan/geometry/fits.h"

#include <ceres/ceres.h>

#include <Eigen/Eigenvalues>
#include <cmath>

namespace uwscan {

std::optional<PlaneFit> FitPlane(const std::vector<Eigen::Vector3d>& points) {
  if (points.size() < 3) return std::nullopt;
  PlaneFit fit;
  for (const auto& p : points) fit.centroid += p;
  fit.centroid /= points.size();
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const auto& p : points) scatter += (p - fit.centroid) * (p - fit.centroid).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter);
  if (solver.info() != Eigen::Success ||
      !(solver.eigenvalues()(1) > 1e-12 * solver.eigenvalues()(2))) {
    return std::nullopt;  // collinear or degenerate
  }
  fit.normal = solver.eigenvectors().col(0).normalized();
  double sum = 0.0;
  for (const auto& p : points) {
    const double d = fit.SignedDistance(p);
    sum += d * d;
    fit.max_abs = std::max(fit.max_abs, std::abs(d));
  }
  fit.count = static_cast<int>(points.size());
  fit.rms = std::sqrt(sum / points.size());
  return fit;
}

double CylinderFit::Residual(const Eigen::Vector3d& p) const {
  const Eigen::Vector3d d = p - axis_point;
  return (d - d.dot(axis_direction) * axis_direction).norm() - radius;
}

namespace {

// Radial residual of a point: distance to the axis minus the radius.
struct CylinderResidual {
  explicit CylinderResidual(const Eigen::Vector3d& point) : point_(point) {}
  template <typename T>
  bool operator()(const T* axis_point, const T* direction, const T* radius, T* residual) const {
    using std::sqrt;
    const T norm = sqrt(direction[0] * direction[0] + direction[1] * direction[1] +
                        direction[2] * direction[2]);
    T d[3], along = T(0);
    for (int i = 0; i < 3; ++i) d[i] = T(point_[i]) - axis_point[i];
    for (int i = 0; i < 3; ++i) along += d[i] * direction[i] / norm;
    T perpendicular2 = T(0);
    for (int i = 0; i < 3; ++i) {
      const T r = d[i] - along * direction[i] / norm;
      perpendicular2 += r * r;
    }
    residual[0] = sqrt(perpendicular2 + T(1e-300)) - radius[0];
    return true;
  }
  static ceres::CostFunction* Create(const Eigen::Vector3d& point) {
    return new ceres::AutoDiffCostFunction<CylinderResidual, 1, 3, 3, 1>(
        new CylinderResidual(point));
  }
  Eigen::Vector3d point_;
};

}  // namespace

std::optional<CylinderFit> FitCylinder(const std::vector<Eigen::Vector3d>& points,
                                       const Eigen::Vector3d& initial_direction,
                                       double initial_radius, const Eigen::Vector3d& towards_axis,
                                       double cauchy_scale_m) {
  if (points.size() < 6 || !(initial_radius > 0)) return std::nullopt;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& p : points) centroid += p;
  centroid /= points.size();
  Eigen::Vector3d direction = initial_direction.normalized();
  Eigen::Vector3d axis_point = centroid + initial_radius * towards_axis.normalized();
  double radius = initial_radius;
  ceres::Problem problem;
  for (const auto& p : points) {
    problem.AddResidualBlock(CylinderResidual::Create(p),
                             cauchy_scale_m > 0 ? new ceres::CauchyLoss(cauchy_scale_m) : nullptr,
                             axis_point.data(), direction.data(), &radius);
  }
  problem.SetManifold(direction.data(), new ceres::SphereManifold<3>());
  ceres::Solver::Options options;
  options.max_num_iterations = 100;
  options.function_tolerance = 1e-15;
  options.parameter_tolerance = 1e-15;
  options.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  if (!summary.IsSolutionUsable() || !(radius > 0)) return std::nullopt;
  CylinderFit fit;
  fit.axis_direction = direction.normalized();
  // Report the axis point closest to the centroid.
  fit.axis_point =
      axis_point + (centroid - axis_point).dot(fit.axis_direction) * fit.axis_direction;
  fit.radius = radius;
  fit.count = static_cast<int>(points.size());
  fit.iterations = static_cast<int>(summary.iterations.size());
  double sum = 0.0;
  for (const auto& p : points) sum += std::pow(fit.Residual(p), 2);
  fit.rms = std::sqrt(sum / points.size());
  return fit;
}

}  // namespace uwscan
