#include "uwscan/geometry/sim3_alignment.h"

#include <Eigen/SVD>

namespace uwscan {

// Umeyama, "Least-squares estimation of transformation parameters between
// two point patterns", PAMI 1991, eqs. 34-42.
std::optional<Sim3d> AlignSim3(const std::vector<Eigen::Vector3d>& source,
                               const std::vector<Eigen::Vector3d>& target, bool with_scale) {
  const size_t n = source.size();
  if (n != target.size() || n < 3) return std::nullopt;
  Eigen::Vector3d mean_source = Eigen::Vector3d::Zero(), mean_target = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < n; ++i) {
    mean_source += source[i];
    mean_target += target[i];
  }
  mean_source /= double(n);
  mean_target /= double(n);
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  double variance_source = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d a = source[i] - mean_source;
    covariance += (target[i] - mean_target) * a.transpose();
    variance_source += a.squaredNorm();
  }
  covariance /= double(n);
  variance_source /= double(n);
  if (variance_source < 1e-18) return std::nullopt;
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d singular = svd.singularValues();
  // Rank < 2 (collinear points): the rotation about the line is free.
  if (singular(1) < 1e-12 * std::max(1.0, singular(0))) return std::nullopt;
  Eigen::Matrix3d s = Eigen::Matrix3d::Identity();
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0) s(2, 2) = -1;
  const Eigen::Matrix3d rotation = svd.matrixU() * s * svd.matrixV().transpose();
  Sim3d sim;
  sim.rotation = Eigen::Quaterniond(rotation).normalized();
  sim.scale = with_scale ? (singular.asDiagonal() * s).trace() / variance_source : 1.0;
  sim.translation = mean_target - sim.scale * (rotation * mean_source);
  return sim;
}

}  // namespace uwscan
