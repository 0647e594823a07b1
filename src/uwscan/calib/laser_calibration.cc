#include "uwscan/calib/laser_calibration.h"

#include <ceres/ceres.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <random>

#include "uwscan/calib/laser_costs.h"
#include "uwscan/util/error.h"

namespace uwscan {
namespace {

struct Plane {
  Eigen::Vector3d normal;
  double d;
};

// Total least squares plane through the points (Eberly 2018).
Plane FitPlaneLeastSquares(const std::vector<Eigen::Vector3d>& points,
                           const std::vector<int>& indices) {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (int i : indices) centroid += points[i];
  centroid /= indices.size();
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (int i : indices) {
    const Eigen::Vector3d r = points[i] - centroid;
    scatter += r * r.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter);
  const Eigen::Vector3d normal = solver.eigenvectors().col(0);
  return {normal, normal.dot(centroid)};
}

}  // namespace

void LaserCalibrationOptions::Check() const {
  UWS_CHECK(ransac_threshold_m > 0.0, "RANSAC threshold must be positive");
  UWS_CHECK(ransac_iterations >= 1, "RANSAC iterations must be >= 1");
  UWS_CHECK(min_points >= 3, "min_points must be >= 3");
}

std::vector<Eigen::Vector3d> LaserPointsOnBoard(const Camera& camera,
                                                const Rigid3d& camera_from_board,
                                                const std::vector<Eigen::Vector2d>& pixels) {
  const Eigen::Vector3d normal = camera_from_board.rotation * Eigen::Vector3d::UnitZ();
  const double offset = normal.dot(camera_from_board.translation);
  std::vector<Eigen::Vector3d> points;
  for (const Eigen::Vector2d& pixel : pixels) {
    const auto ray = camera.BackProject(pixel);
    if (!ray) continue;
    const double denominator = normal.dot(ray->direction);
    if (std::abs(denominator) < 1e-9) continue;
    const double lambda = (offset - normal.dot(ray->origin)) / denominator;
    if (lambda > 0.0) points.push_back(ray->At(lambda));
  }
  return points;
}

LaserCalibrationResult FitLaserProjector(const std::vector<Eigen::Vector3d>& points,
                                         const LaserCalibrationOptions& options) {
  options.Check();
  UWS_CHECK(static_cast<int>(points.size()) >= options.min_points, "laser calibration: only ",
            points.size(), " laser points on the boards, need at least ", options.min_points);
  LaserCalibrationResult result;
  result.points = static_cast<int>(points.size());

  // RANSAC on 3-point planes, then least squares on the inliers.
  std::mt19937 rng(options.seed);
  std::uniform_int_distribution<int> pick(0, static_cast<int>(points.size()) - 1);
  std::vector<int> best;
  for (int iteration = 0; iteration < options.ransac_iterations; ++iteration) {
    const Eigen::Vector3d& a = points[pick(rng)];
    const Eigen::Vector3d& b = points[pick(rng)];
    const Eigen::Vector3d& c = points[pick(rng)];
    const Eigen::Vector3d cross = (b - a).cross(c - a);
    if (cross.norm() < 1e-12) continue;
    const Eigen::Vector3d normal = cross.normalized();
    std::vector<int> inliers;
    for (size_t i = 0; i < points.size(); ++i) {
      if (std::abs(normal.dot(points[i] - a)) < options.ransac_threshold_m) inliers.push_back(i);
    }
    if (inliers.size() > best.size()) best = std::move(inliers);
  }
  UWS_CHECK(best.size() >= 3, "laser calibration: no plane found in the laser points");
  Plane plane = FitPlaneLeastSquares(points, best);
  // Re-collect inliers of the LS plane.
  best.clear();
  for (size_t i = 0; i < points.size(); ++i) {
    if (std::abs(plane.normal.dot(points[i]) - plane.d) < options.ransac_threshold_m) {
      best.push_back(i);
    }
  }
  plane = FitPlaneLeastSquares(points, best);
  // Points on one board line are collinear: the sheet needs two distances.
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (int i : best) centroid += points[i];
  centroid /= best.size();
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (int i : best) scatter += (points[i] - centroid) * (points[i] - centroid).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> spread(scatter / best.size());
  UWS_CHECK(std::sqrt(std::max(0.0, spread.eigenvalues()(1))) > options.min_depth_spread_m / 4,
            "laser calibration: the laser points are (nearly) collinear; put the board at two "
            "or more distances");
  if (plane.normal.dot(centroid) < 0.0) plane = {-plane.normal, -plane.d};
  result.plane_normal = plane.normal;
  result.plane_d = plane.d;
  result.inliers = static_cast<int>(best.size());
  double sum_sq = 0.0;
  for (int i : best) sum_sq += std::pow(plane.normal.dot(points[i]) - plane.d, 2);
  result.plane_rms_m = std::sqrt(sum_sq / best.size());

  // Initial projector frame: y = sheet normal, z towards the points, x along the line.
  Eigen::Vector3d centre = plane.d * plane.normal;  // foot of the perpendicular from the camera
  if (options.nominal_camera_from_laser) {
    const Eigen::Vector3d t = options.nominal_camera_from_laser->translation;
    centre = t - (plane.normal.dot(t) - plane.d) * plane.normal;
  }
  Eigen::Vector3d z_axis = centroid - centre;
  z_axis -= z_axis.dot(plane.normal) * plane.normal;
  UWS_CHECK(z_axis.norm() > 1e-6, "laser calibration: degenerate projector centre");
  z_axis.normalize();
  const Eigen::Vector3d y_axis = plane.normal;
  const Eigen::Vector3d x_axis = y_axis.cross(z_axis);
  Eigen::Matrix3d rotation;
  rotation << x_axis, y_axis, z_axis;
  Eigen::Quaterniond q(rotation);
  if (options.nominal_camera_from_laser &&
      options.nominal_camera_from_laser->RotationMatrix().col(0).dot(x_axis) < 0.0) {
    // Keep the nominal direction of the line (x) and hence the sign of p1.
    q = q * Eigen::Quaterniond(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()));
  }
  double q_block[4] = {q.w(), q.x(), q.y(), q.z()};
  double t_block[3] = {centre.x(), centre.y(), centre.z()};
  double p1_block[1] = {0.0};

  // Refinement on eq. 4.30. The centre may move only across the sheet: along
  // the sheet it is a gauge freedom of the plane, and the apex depth of the
  // bend is not observable from boards at 0.3-0.5 m either (measured: it
  // drifts to metres), so it stays at the nominal centre.
  ceres::Problem problem;
  for (int i : best) {
    problem.AddResidualBlock(LaserSheetCost::Create(points[i]), nullptr, q_block, t_block,
                             p1_block);
  }
  problem.SetManifold(q_block, new ceres::QuaternionManifold);
  problem.SetManifold(t_block, new SubspaceManifold({plane.normal}));
  if (!options.refine_bend) problem.SetParameterBlockConstant(p1_block);
  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::DENSE_QR;
  solver_options.max_num_iterations = 100;
  solver_options.function_tolerance = 1e-14;
  solver_options.parameter_tolerance = 1e-14;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  UWS_CHECK(summary.IsSolutionUsable(), "laser calibration: the solver failed: ", summary.message);
  result.iterations = static_cast<int>(summary.iterations.size()) - 1;

  LineProjector& laser = result.laser;
  laser.camera_from_laser =
      Rigid3d(Eigen::Quaterniond(q_block[0], q_block[1], q_block[2], q_block[3]).normalized(),
              Eigen::Vector3d(t_block[0], t_block[1], t_block[2]));
  laser.p1 = p1_block[0];
  sum_sq = 0.0;
  for (int i : best) {
    const Eigen::Vector3d local = laser.camera_from_laser.Inverse() * points[i];
    const double residual = laser.SheetResidual(points[i]).value_or(0.0);
    sum_sq += std::pow(residual * local.z(), 2);  // angle -> distance at the point's range
  }
  result.sheet_rms_m = std::sqrt(sum_sq / best.size());
  const Eigen::Vector3d sheet_normal = laser.camera_from_laser.RotationMatrix().col(1);
  result.baseline_m = std::abs(sheet_normal.dot(laser.camera_from_laser.translation));
  result.sheet_angle_deg = std::acos(std::min(1.0, std::abs(sheet_normal.x()))) * 180.0 / M_PI;
  return result;
}

LaserCalibrationResult CalibrateLaser(const Camera& camera, const std::vector<LaserView>& views,
                                      const LaserCalibrationOptions& options,
                                      const ServoAxis* servo) {
  options.Check();
  UWS_CHECK(!views.empty(), "laser calibration: no view with a board and laser points");
  std::vector<Eigen::Vector3d> points;
  std::vector<int> per_view;
  for (const LaserView& view : views) {
    std::vector<Eigen::Vector3d> on_board =
        LaserPointsOnBoard(camera, view.camera_from_board, view.laser_pixels);
    per_view.push_back(static_cast<int>(on_board.size()));
    if (servo) {
      // Back to the servo's zero: rotate by -angle about the axis (§6.5).
      const Eigen::AngleAxisd back(-view.servo_angle_rad, servo->direction.normalized());
      for (Eigen::Vector3d& p : on_board) p = back * (p - servo->point) + servo->point;
    }
    points.insert(points.end(), on_board.begin(), on_board.end());
  }
  if (!servo) {
    int views_with_points = 0;
    for (int count : per_view) views_with_points += count > 0;
    UWS_CHECK(views_with_points >= 2, "laser calibration: laser points on ", views_with_points,
              " board pose(s); put the board at two or more distances");
  }
  LaserCalibrationResult result = FitLaserProjector(points, options);
  result.view_points = per_view;
  return result;
}

}  // namespace uwscan
