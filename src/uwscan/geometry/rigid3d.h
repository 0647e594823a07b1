// Rigid transform (unit quaternion + translation), named by its frames:
// `a_from_c = a_from_b * b_from_c`.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

namespace uwscan {

struct Rigid3d {
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  Rigid3d() = default;
  // Normalises q unless it is already unit to the last bit, so that a pose
  // read back from a file reproduces the written one exactly.
  Rigid3d(const Eigen::Quaterniond& q, const Eigen::Vector3d& t)
      : rotation(std::abs(q.squaredNorm() - 1.0) > 1e-15 ? q.normalized() : q), translation(t) {}

  Eigen::Vector3d operator*(const Eigen::Vector3d& point) const {
    return rotation * point + translation;
  }
  Rigid3d operator*(const Rigid3d& other) const {
    return Rigid3d(rotation * other.rotation, rotation * other.translation + translation);
  }
  Rigid3d Inverse() const {
    const Eigen::Quaterniond inverse = rotation.conjugate();
    return Rigid3d(inverse, -(inverse * translation));
  }
  Eigen::Matrix3d RotationMatrix() const { return rotation.toRotationMatrix(); }
};

}  // namespace uwscan
