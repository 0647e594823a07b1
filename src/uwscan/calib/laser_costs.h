// Ceres pieces for the line projector refinement (thesis §4.4 "Line
// Projector Refinement", eq. 4.30).
#pragma once

#include <ceres/autodiff_cost_function.h>
#include <ceres/manifold.h>

#include <Eigen/Core>

#include "uwscan/sensor/line_projector.h"

namespace uwscan {

// Distance of a 3D laser point (camera frame) to the bent sheet, eq. 4.30:
//   d = x_y / x_z - p1 (x_x / x_z)^2,  x = R^T (X - C).
// Blocks: camera_from_laser q[4] (w x y z), t[3], p1[1].
class LaserSheetCost {
 public:
  explicit LaserSheetCost(const Eigen::Vector3d& point_in_camera)
      : point_in_camera_(point_in_camera) {}

  template <typename T>
  bool operator()(const T* q, const T* t, const T* p1, T* residual) const {
    const T point[3] = {T(point_in_camera_.x()), T(point_in_camera_.y()), T(point_in_camera_.z())};
    return LineProjectorModel::SheetResidual(q, t, p1[0], point, residual);
  }

  static ceres::CostFunction* Create(const Eigen::Vector3d& point_in_camera) {
    return new ceres::AutoDiffCostFunction<LaserSheetCost, 1, 4, 3, 1>(
        new LaserSheetCost(point_in_camera));
  }

 private:
  Eigen::Vector3d point_in_camera_;
};

// A point that may move only within the span of orthonormal directions (the
// rest of R^3 is held): the projector centre across the sheet.
class SubspaceManifold : public ceres::Manifold {
 public:
  explicit SubspaceManifold(std::vector<Eigen::Vector3d> directions)
      : directions_(std::move(directions)) {}
  int AmbientSize() const override { return 3; }
  int TangentSize() const override { return static_cast<int>(directions_.size()); }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override {
    for (int i = 0; i < 3; ++i) {
      x_plus_delta[i] = x[i];
      for (size_t k = 0; k < directions_.size(); ++k) x_plus_delta[i] += delta[k] * directions_[k][i];
    }
    return true;
  }
  bool PlusJacobian(const double*, double* jacobian) const override {
    const int n = TangentSize();
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < n; ++k) jacobian[i * n + k] = directions_[k][i];
    return true;
  }
  bool Minus(const double* y, const double* x, double* y_minus_x) const override {
    for (size_t k = 0; k < directions_.size(); ++k) {
      y_minus_x[k] = 0.0;
      for (int i = 0; i < 3; ++i) y_minus_x[k] += (y[i] - x[i]) * directions_[k][i];
    }
    return true;
  }
  bool MinusJacobian(const double*, double* jacobian) const override {
    for (size_t k = 0; k < directions_.size(); ++k)
      for (int i = 0; i < 3; ++i) jacobian[k * 3 + i] = directions_[k][i];
    return true;
  }

 private:
  std::vector<Eigen::Vector3d> directions_;  // orthonormal
};

}  // namespace uwscan
