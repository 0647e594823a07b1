#include "uwscan/fusion/pose_refinement.h"

#include <ceres/ceres.h>

#include "uwscan/vo/cost_functions.h"

namespace uwscan::fusion {
namespace {

// Signed distance of a camera-frame laser point, moved to the world with
// the pose, from a measured surface plane: n . (R^T (p - t) - c) / sigma,
// with the pose as camera_from_world (q: Eigen x y z w, t).
struct ProfileToPlaneCost {
  ProfileToPlaneCost(const Eigen::Vector3d& point_camera, const Eigen::Vector3d& plane_point,
                     const Eigen::Vector3d& normal, double sigma)
      : point_(point_camera), plane_point_(plane_point), normal_(normal), inverse_sigma_(1.0 / sigma) {}
  template <typename T>
  bool operator()(const T* q, const T* t, T* residual) const {
    const Eigen::Quaternion<T> rotation(q[3], q[0], q[1], q[2]);
    const Eigen::Matrix<T, 3, 1> translation(t[0], t[1], t[2]);
    const Eigen::Matrix<T, 3, 1> world =
        rotation.conjugate() * (point_.cast<T>() - translation);
    residual[0] = normal_.cast<T>().dot(world - plane_point_.cast<T>()) * T(inverse_sigma_);
    return true;
  }
  static ceres::CostFunction* Create(const Eigen::Vector3d& point_camera,
                                     const Eigen::Vector3d& plane_point,
                                     const Eigen::Vector3d& normal, double sigma) {
    return new ceres::AutoDiffCostFunction<ProfileToPlaneCost, 1, 4, 3>(
        new ProfileToPlaneCost(point_camera, plane_point, normal, sigma));
  }
  Eigen::Vector3d point_, plane_point_, normal_;
  double inverse_sigma_;
};

}  // namespace

PoseRefinementResult RefinePoseWithProfile(const Camera& camera, const vo::Odometry& odometry,
                                           const Rigid3d& world_from_camera,
                                           const laser::Profile& profile,
                                           const SurfaceModel& surface,
                                           const PoseRefinementOptions& options) {
  PoseRefinementResult result;
  result.world_from_camera = world_from_camera;
  const Rigid3d camera_from_world = world_from_camera.Inverse();
  double q[4] = {camera_from_world.rotation.x(), camera_from_world.rotation.y(),
                 camera_from_world.rotation.z(), camera_from_world.rotation.w()};
  Eigen::Vector3d t = camera_from_world.translation;
  ceres::Problem problem;
  const vo::CameraParams params(camera);
  for (const auto& track : odometry.tracks()) {
    const vo::MapPoint* point = odometry.map().FindPoint(track.id);
    if (!point) continue;
    const vo::ReprojectionCost cost(params, ProjectionMethod::kExact, 2, track.pixel,
                                    options.feature_sigma_px);
    problem.AddResidualBlock(vo::PoseReprojectionCost::Create(cost, point->position_world),
                             new ceres::HuberLoss(3.0), q, t.data());
    ++result.feature_residuals;
  }
  const size_t step = std::max<size_t>(1, profile.points.size() / options.max_profile_points);
  for (size_t i = 0; i < profile.points.size(); i += step) {
    const Eigen::Vector3d& p = profile.points[i].point_in_camera;
    const auto plane = surface.LocalPlane(world_from_camera * p);
    if (!plane) continue;
    problem.AddResidualBlock(
        ProfileToPlaneCost::Create(p, plane->first, plane->second, options.laser_sigma_m),
        new ceres::CauchyLoss(options.cauchy_scale), q, t.data());  // eq. 5.3
    ++result.laser_residuals;
  }
  if (result.feature_residuals < 6 || result.laser_residuals < options.min_profile_points) {
    return result;
  }
  problem.SetManifold(q, new ceres::EigenQuaternionManifold);
  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::DENSE_QR;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  if (!summary.IsSolutionUsable()) return result;
  const Rigid3d refined(Eigen::Quaterniond(q[3], q[0], q[1], q[2]), t);
  result.world_from_camera = refined.Inverse();
  result.refined = true;
  return result;
}

}  // namespace uwscan::fusion
