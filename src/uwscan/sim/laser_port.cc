#include "uwscan/sim/laser_port.h"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <cmath>
#include <vector>

#include "uwscan/sensor/flatport.h"
#include "uwscan/util/error.h"

namespace uwscan::sim {
namespace {

// Residual of eq. 4.30 times depth (metres off the sheet) of a point given
// in the bare laser's frame, for the model frame (angle-axis r, translation
// (0, ty, tz)) and bend p1.
struct SheetPointCost {
  explicit SheetPointCost(const Eigen::Vector3d& point) : point_(point) {}

  template <typename T>
  bool operator()(const T* rotation, const T* translation, const T* p1, T* residual) const {
    const T shifted[3] = {T(point_.x()), T(point_.y()) - translation[0],
                          T(point_.z()) - translation[1]};
    const T inverse[3] = {-rotation[0], -rotation[1], -rotation[2]};
    T p[3];
    ceres::AngleAxisRotatePoint(inverse, shifted, p);
    const T x = p[0] / p[2];
    residual[0] = (p[1] / p[2] - p1[0] * x * x) * p[2];
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Vector3d& point) {
    return new ceres::AutoDiffCostFunction<SheetPointCost, 1, 3, 2, 1>(new SheetPointCost(point));
  }

  Eigen::Vector3d point_;
};

}  // namespace

LaserPortFit FitLaserBehindPort(const FlatPort& port, double fan_angle_rad, double min_range_m,
                                double max_range_m) {
  const auto params = port.Params();
  std::vector<Eigen::Vector3d> points;
  const int rays = 41, depths = 6;
  const double half = std::tan(0.5 * fan_angle_rad);
  for (int i = 0; i < rays; ++i) {
    const double x = half * (2.0 * i / (rays - 1) - 1.0);
    const double ray[3] = {x, 0.0, 1.0};
    Eigen::Vector3d origin, direction;
    UWS_CHECK(FlatPortModel::RefractRay(port.normal.data(), params.data(), ray, origin.data(),
                                        direction.data()),
              "laser port: the light sheet does not pass the port (fan or tilt too large)");
    for (int k = 0; k < depths; ++k) {
      const double range = min_range_m + (max_range_m - min_range_m) * k / (depths - 1);
      points.push_back(origin + range * direction);
    }
  }
  double rotation[3] = {0, 0, 0}, translation[2] = {0, 0}, p1 = 0;
  ceres::Problem problem;
  for (const auto& point : points) {
    problem.AddResidualBlock(SheetPointCost::Create(point), nullptr, rotation, translation, &p1);
  }
  ceres::Solver::Options options;
  options.max_num_iterations = 100;
  options.function_tolerance = 1e-14;
  options.parameter_tolerance = 1e-14;
  options.gradient_tolerance = 1e-16;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);

  LaserPortFit fit;
  const Eigen::Vector3d axis_angle(rotation[0], rotation[1], rotation[2]);
  const double angle = axis_angle.norm();
  const Eigen::Quaterniond q =
      angle > 0 ? Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis_angle / angle))
                : Eigen::Quaterniond::Identity();
  fit.inner_from_model = Rigid3d(q, Eigen::Vector3d(0, translation[0], translation[1]));
  fit.p1 = p1;
  double sum = 0;
  for (const auto& point : points) {
    double r;
    const SheetPointCost cost(point);
    cost(rotation, translation, &p1, &r);
    sum += r * r;
    fit.max_m = std::max(fit.max_m, std::abs(r));
  }
  fit.rms_m = std::sqrt(sum / points.size());
  return fit;
}

}  // namespace uwscan::sim
