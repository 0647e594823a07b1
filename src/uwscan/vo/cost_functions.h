// Ceres cost functors of the visual odometry. Poses are camera_from_world as
// an Eigen-ordered unit quaternion (x, y, z, w; ceres::EigenQuaternionManifold)
// and a translation; points are in the world frame.
#pragma once

#include <ceres/ceres.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <type_traits>

#include "uwscan/sensor/camera.h"
#include "uwscan/sensor/flatport.h"
#include "uwscan/sensor/pinhole.h"

namespace uwscan::vo {

// Camera parameters as plain arrays (held constant in the VO).
struct CameraParams {
  double intrinsics[4];
  double distortion[5];
  double normal[3];
  double port[5];
  bool flat_port = true;
  explicit CameraParams(const Camera& camera) {
    std::copy(camera.intrinsics.begin(), camera.intrinsics.end(), intrinsics);
    std::copy(camera.distortion.begin(), camera.distortion.end(), distortion);
    for (int i = 0; i < 3; ++i) normal[i] = camera.port.normal[i];
    const auto p = camera.port.Params();
    std::copy(p.begin(), p.end(), port);
    flat_port = camera.IsFlatPort();
  }
};

// point_in_camera = R(q) * point_world + t.
template <typename T>
void TransformToCamera(const T* q, const T* t, const T* point_world, T* point_camera) {
  const Eigen::Map<const Eigen::Quaternion<T>> rotation(q);
  const Eigen::Map<const Eigen::Matrix<T, 3, 1>> p(point_world);
  Eigen::Map<Eigen::Matrix<T, 3, 1>> out(point_camera);
  out = rotation * p + Eigen::Map<const Eigen::Matrix<T, 3, 1>>(t);
}

// Re-projection residual (thesis §5.2, windowed bundle adjustment): observed
// pixel minus the projection of the point through
//   kExact  : the exact flat-port model (eqs. 4.9-4.12 solved for the pixel),
//   kTaylor : the thesis Taylor projection (eqs. 4.13-4.26) started at the
//             observed pixel, `taylor_iterations` steps,
//   kPinhole: pinhole + Brown (for a pinhole camera, or to ignore the port),
// divided by sigma_px. Returns false where the model cannot project.
class ReprojectionCost {
 public:
  ReprojectionCost(const CameraParams& camera, ProjectionMethod method, int taylor_iterations,
                   const Eigen::Vector2d& observed, double sigma_px)
      : camera_(camera),
        method_(camera.flat_port ? method : ProjectionMethod::kPinhole),
        iterations_(taylor_iterations),
        observed_(observed),
        inverse_sigma_(1.0 / sigma_px) {}

  template <typename T>
  bool Project(const T* point_camera, T* pixel) const {
    T intrinsics[4], distortion[5];
    for (int i = 0; i < 4; ++i) intrinsics[i] = T(camera_.intrinsics[i]);
    for (int i = 0; i < 5; ++i) distortion[i] = T(camera_.distortion[i]);
    if (method_ == ProjectionMethod::kPinhole) {
      return PinholeModel::Project(intrinsics, distortion, point_camera, pixel);
    }
    T normal[3], port[5];
    for (int i = 0; i < 3; ++i) normal[i] = T(camera_.normal[i]);
    for (int i = 0; i < 5; ++i) port[i] = T(camera_.port[i]);
    if (method_ == ProjectionMethod::kExact) {
      return FlatPortModel::ProjectExact(intrinsics, distortion, normal, port, point_camera, pixel);
    }
    const T start[2] = {T(observed_.x()), T(observed_.y())};
    return FlatPortModel::ProjectTaylorFromPixel(intrinsics, distortion, normal, port, point_camera,
                                                 start, iterations_, pixel);
  }

  // The residual of a point already in the camera frame.
  template <typename T>
  bool Residual(const T* point_camera, T* residual) const {
    T pixel[2];
    if (!Project(point_camera, pixel)) return false;
    residual[0] = (pixel[0] - T(observed_.x())) * T(inverse_sigma_);
    residual[1] = (pixel[1] - T(observed_.y())) * T(inverse_sigma_);
    return true;
  }

  template <typename T>
  bool operator()(const T* q, const T* t, const T* point_world, T* residual) const {
    T point_camera[3];
    TransformToCamera(q, t, point_world, point_camera);
    return Residual(point_camera, residual);
  }

  // Parameter blocks q (4), t (3), point_world (3); derivatives by the
  // chain rule (ChainedReprojection below).
  static ceres::CostFunction* Create(const CameraParams& camera, ProjectionMethod method,
                                     int taylor_iterations, const Eigen::Vector2d& observed,
                                     double sigma_px = 1.0);

 private:
  CameraParams camera_;
  ProjectionMethod method_;
  int iterations_;
  Eigen::Vector2d observed_;
  double inverse_sigma_;
};

// The same residual with the point held fixed: pose-only refinement after
// P3P (thesis §5.2, "Camera Pose Estimation").
class PoseReprojectionCost {
 public:
  PoseReprojectionCost(const ReprojectionCost& cost, const Eigen::Vector3d& point_world)
      : cost_(cost), point_(point_world) {}
  template <typename T>
  bool operator()(const T* q, const T* t, T* residual) const {
    const T point[3] = {T(point_.x()), T(point_.y()), T(point_.z())};
    return cost_(q, t, point, residual);
  }
  // Parameter blocks q (4), t (3).
  static ceres::CostFunction* Create(const ReprojectionCost& cost,
                                     const Eigen::Vector3d& point_world);

 private:
  ReprojectionCost cost_;
  Eigen::Vector3d point_;
};

// Laser range constraint (thesis §5.4, scale equalisation): the distance of
// the point from the origin of its viewing ray (outer port surface, or the
// centre for a pinhole) equals the range measured by laser triangulation,
//   r = (|R p + t - o| - range) / sigma.
class RangeCost {
 public:
  RangeCost(const Eigen::Vector3d& ray_origin_camera, double range_m, double sigma_m)
      : origin_(ray_origin_camera), range_(range_m), inverse_sigma_(1.0 / sigma_m) {}
  template <typename T>
  bool operator()(const T* q, const T* t, const T* point_world, T* residual) const {
    using std::sqrt;
    T p[3];
    TransformToCamera(q, t, point_world, p);
    const T dx = p[0] - T(origin_.x()), dy = p[1] - T(origin_.y()), dz = p[2] - T(origin_.z());
    const T squared = dx * dx + dy * dy + dz * dz;
    if (!(std::isfinite(ScalarOf(squared)) && ScalarOf(squared) > 1e-18)) return false;
    residual[0] = (sqrt(squared) - T(range_)) * T(inverse_sigma_);
    return true;
  }
  static ceres::CostFunction* Create(const Eigen::Vector3d& ray_origin_camera, double range_m,
                                     double sigma_m) {
    return new ceres::AutoDiffCostFunction<RangeCost, 1, 4, 3, 3>(
        new RangeCost(ray_origin_camera, range_m, sigma_m));
  }

 private:
  Eigen::Vector3d origin_;
  double range_;
  double inverse_sigma_;
};

// A ReprojectionCost differentiated in two stages and chained: the rigid
// transform over the pose (and point) parameters, the projection only over
// the three coordinates of the point in the camera frame. The values and
// derivatives are those of automatic differentiation over all parameters,
// but the refractive projection, nearly all of the cost, runs on Jets of 3
// instead of 7 (pose refinement) or 10 (bundle adjustment) derivatives.
template <bool kPointIsParameter>
class ChainedReprojection final
    : public std::conditional_t<kPointIsParameter, ceres::SizedCostFunction<2, 4, 3, 3>,
                                ceres::SizedCostFunction<2, 4, 3>> {
 public:
  ChainedReprojection(const ReprojectionCost& cost, const Eigen::Vector3d& fixed_point)
      : cost_(cost), fixed_point_(fixed_point) {}

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const double* q = parameters[0];
    const double* t = parameters[1];
    const double* point = kPointIsParameter ? parameters[2] : fixed_point_.data();
    if (!jacobians) {
      double point_camera[3];
      TransformToCamera(q, t, point, point_camera);
      return cost_.Residual(point_camera, residuals);
    }
    // Stage 1: point_camera and its derivatives over q (and the point);
    // over t it is the identity.
    constexpr int kTransformDims = kPointIsParameter ? 7 : 4;
    using TransformJet = ceres::Jet<double, kTransformDims>;
    TransformJet qj[4], pj[3], tj[3], cj[3];
    for (int i = 0; i < 4; ++i) qj[i] = TransformJet(q[i], i);
    for (int i = 0; i < 3; ++i) {
      tj[i] = TransformJet(t[i]);
      pj[i] = kPointIsParameter ? TransformJet(point[i], 4 + i) : TransformJet(point[i]);
    }
    TransformToCamera(qj, tj, pj, cj);
    // Stage 2: the residual and its derivatives over point_camera.
    using ProjectionJet = ceres::Jet<double, 3>;
    ProjectionJet camera_point[3], residual[2];
    for (int i = 0; i < 3; ++i) camera_point[i] = ProjectionJet(cj[i].a, i);
    if (!cost_.Residual(camera_point, residual)) return false;
    residuals[0] = residual[0].a;
    residuals[1] = residual[1].a;
    // Chain: d r / d x = (d r / d point_camera) (d point_camera / d x).
    for (int r = 0; r < 2; ++r) {
      if (jacobians[0]) {
        for (int c = 0; c < 4; ++c) {
          double sum = 0.0;
          for (int k = 0; k < 3; ++k) sum += residual[r].v[k] * cj[k].v[c];
          jacobians[0][r * 4 + c] = sum;
        }
      }
      if (jacobians[1]) {
        for (int c = 0; c < 3; ++c) jacobians[1][r * 3 + c] = residual[r].v[c];
      }
      if (kPointIsParameter && jacobians[2]) {
        for (int c = 0; c < 3; ++c) {
          double sum = 0.0;
          for (int k = 0; k < 3; ++k) sum += residual[r].v[k] * cj[k].v[4 + c];
          jacobians[2][r * 3 + c] = sum;
        }
      }
    }
    return true;
  }

 private:
  ReprojectionCost cost_;
  Eigen::Vector3d fixed_point_;  // when the point is not a parameter
};

inline ceres::CostFunction* ReprojectionCost::Create(const CameraParams& camera,
                                                     ProjectionMethod method, int taylor_iterations,
                                                     const Eigen::Vector2d& observed,
                                                     double sigma_px) {
  return new ChainedReprojection<true>(
      ReprojectionCost(camera, method, taylor_iterations, observed, sigma_px),
      Eigen::Vector3d::Zero());
}

inline ceres::CostFunction* PoseReprojectionCost::Create(const ReprojectionCost& cost,
                                                         const Eigen::Vector3d& point_world) {
  return new ChainedReprojection<false>(cost, point_world);
}

}  // namespace uwscan::vo
