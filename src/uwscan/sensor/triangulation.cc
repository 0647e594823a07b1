#include "uwscan/sensor/triangulation.h"

#include <Eigen/Eigenvalues>

namespace uwscan {

std::optional<Eigen::Vector3d> TriangulateRays(const std::vector<Ray>& rays) {
  if (rays.size() < 2) return std::nullopt;
  Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (const Ray& ray : rays) {
    const Eigen::Vector3d d = ray.direction.normalized();
    const Eigen::Matrix3d projector = Eigen::Matrix3d::Identity() - d * d.transpose();
    a += projector;
    b += projector * ray.origin;
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(a);
  if (eigen.eigenvalues()(0) < 1e-10 * eigen.eigenvalues()(2)) return std::nullopt;
  const Eigen::Vector3d point = a.ldlt().solve(b);
  for (const Ray& ray : rays) {
    if ((point - ray.origin).dot(ray.direction) <= 0) return std::nullopt;
  }
  return point;
}

}  // namespace uwscan
