// Least-squares shape fits used by the evaluation (thesis ch. 6: plane fits
// on the target, cylinder fit on the propeller shaft).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

namespace uwscan {

struct PlaneFit {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // unit
  double rms = 0.0;  // of signed distances (= their standard deviation, zero mean)
  double max_abs = 0.0;
  int count = 0;
  double SignedDistance(const Eigen::Vector3d& p) const { return normal.dot(p - centroid); }
};

// Total least squares (PCA). Needs at least 3 non-collinear points.
std::optional<PlaneFit> FitPlane(const std::vector<Eigen::Vector3d>& points);

struct CylinderFit {
  Eigen::Vector3d axis_point = Eigen::Vector3d::Zero();       // closest axis point to the centroid
  Eigen::Vector3d axis_direction = Eigen::Vector3d::UnitZ();  // unit
  double radius = 0.0;
  double rms = 0.0;  // of radial residuals |distance to axis| - radius
  int count = 0;
  int iterations = 0;
  double Residual(const Eigen::Vector3d& p) const;
};

// Geometric least squares with Ceres from an initial axis direction and
// radius (e.g. known roughly from the scene); the axis point starts at the
// centroid shifted away from the points by the radius along `towards_axis`.
// With `cauchy_scale_m` > 0 the residuals go through a Cauchy loss of that
// scale, so that a few gross outliers do not pull the cylinder off the rest
// (`rms` is still of all the points' plain residuals).
std::optional<CylinderFit> FitCylinder(const std::vector<Eigen::Vector3d>& points,
                                       const Eigen::Vector3d& initial_direction,
                                       double initial_radius, const Eigen::Vector3d& towards_axis,
                                       double cauchy_scale_m = 0.0);

}  // namespace uwscan
