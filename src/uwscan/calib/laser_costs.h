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

// A point constrained to a line x0 + s * direction: ambient size 3, tangent
// size 1. Used for the projector centre, which points on the sheet only fix
// across the sheet (moving it within the sheet is a gauge freedom for p1 = 0).
class LineManifold : public ceres::Manifold {
 public:
  explicit LineManifold(const Eigen::Vector3d& direction) : direction_(direction.normalized()) {}
  int AmbientSize() const override { return 3; }
  int TangentSize() const override { return 1; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override {
    for (int i = 0; i < 3; ++i) x_plus_delta[i] = x[i] + delta[0] * direction_[i];
    return true;
  }
  bool PlusJacobian(const double*, double* jacobian) const override {
    for (int i = 0; i < 3; ++i) jacobian[i] = direction_[i];
    return true;
  }
  bool Minus(const double* y, const double* x, double* y_minus_x) const override {
    y_minus_x[0] = 0.0;
    for (int i = 0; i < 3; ++i) y_minus_x[0] += (y[i] - x[i]) * direction_[i];
    return true;
  }
  bool MinusJacobian(const double*, double* jacobian) const override {
    for (int i = 0; i < 3; ++i) jacobian[i] = direction_[i];
    return true;
  }

 private:
  Eigen::Vector3d direction_;
};

}  // namespace uwscan
