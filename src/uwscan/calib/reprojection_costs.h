// Ceres cost functors for camera calibration from checkerboard corners
// (thesis §4.4, "Camera Model Refinement"). Parameter blocks are separate so
// any group can be held constant:
//   intrinsics[4]  fx fy cx cy
//   distortion[5]  k1 k2 p1 p2 k3
//   normal[3]      port normal, camera -> water (on ceres::SphereManifold<3>)
//   d_air[1]       camera centre to inner glass surface (m)
//   media[4]       d_glass, n_air, n_glass, n_water (usually constant; n_water
//                  may be freed with a ceres::SubsetManifold, Tab. 4.11)
//   board_q[4]     camera_from_board rotation (w x y z, ceres::QuaternionManifold)
//   board_t[3]     camera_from_board translation (m)
#pragma once

#include <ceres/autodiff_cost_function.h>
#include <ceres/rotation.h>

#include <Eigen/Core>

#include "uwscan/sensor/flatport.h"
#include "uwscan/sensor/pinhole.h"

namespace uwscan {

// Board point into the camera frame: X_c = R(q) X_b + t.
template <typename T>
inline void BoardToCamera(const T* board_q, const T* board_t, const Eigen::Vector3d& point_in_board,
                          T* point_in_camera) {
  const T point[3] = {T(point_in_board.x()), T(point_in_board.y()), T(point_in_board.z())};
  ceres::UnitQuaternionRotatePoint(board_q, point, point_in_camera);
  for (int i = 0; i < 3; ++i) point_in_camera[i] += board_t[i];
}

// Pinhole + Brown re-projection error (eqs. 4.2, 4.8; Zhang's calibration).
class PinholeReprojectionCost {
 public:
  PinholeReprojectionCost(const Eigen::Vector2d& observed, const Eigen::Vector3d& point_in_board)
      : observed_(observed), point_in_board_(point_in_board) {}

  template <typename T>
  bool operator()(const T* intrinsics, const T* distortion, const T* board_q, const T* board_t,
                  T* residual) const {
    T point[3], pixel[2];
    BoardToCamera(board_q, board_t, point_in_board_, point);
    if (!PinholeModel::Project(intrinsics, distortion, point, pixel)) return false;
    residual[0] = pixel[0] - T(observed_.x());
    residual[1] = pixel[1] - T(observed_.y());
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Vector2d& observed,
                                     const Eigen::Vector3d& point_in_board) {
    return new ceres::AutoDiffCostFunction<PinholeReprojectionCost, 2, 4, 5, 4, 3>(
        new PinholeReprojectionCost(observed, point_in_board));
  }

 private:
  Eigen::Vector2d observed_;
  Eigen::Vector3d point_in_board_;
};

enum class FlatPortResidualType {
  kExact,   // exact refractive forward projection
  kTaylor,  // Taylor projection centred at the measured corner (§4.4, eqs. 4.13-4.26)
};

// Flat-port re-projection error. kTaylor is the thesis's residual: the
// refractive forward projection expanded at the measured corner, so one or
// two steps suffice because the centre is within noise of the answer.
class FlatPortReprojectionCost {
 public:
  FlatPortReprojectionCost(const Eigen::Vector2d& observed, const Eigen::Vector3d& point_in_board,
                           FlatPortResidualType type, int taylor_iterations)
      : observed_(observed),
        point_in_board_(point_in_board),
        type_(type),
        taylor_iterations_(taylor_iterations) {}

  template <typename T>
  bool operator()(const T* intrinsics, const T* distortion, const T* normal, const T* d_air,
                  const T* media, const T* board_q, const T* board_t, T* residual) const {
    T point[3], pixel[2];
    BoardToCamera(board_q, board_t, point_in_board_, point);
    const T port[5] = {d_air[0], media[0], media[1], media[2], media[3]};
    bool ok;
    if (type_ == FlatPortResidualType::kExact) {
      ok = FlatPortModel::ProjectExact(intrinsics, distortion, normal, port, point, pixel);
    } else {
      const T start[2] = {T(observed_.x()), T(observed_.y())};
      ok = FlatPortModel::ProjectTaylorFromPixel(intrinsics, distortion, normal, port, point, start,
                                                 taylor_iterations_, pixel);
    }
    if (!ok) return false;
    residual[0] = pixel[0] - T(observed_.x());
    residual[1] = pixel[1] - T(observed_.y());
    return true;
  }

  static ceres::CostFunction* Create(const Eigen::Vector2d& observed,
                                     const Eigen::Vector3d& point_in_board,
                                     FlatPortResidualType type = FlatPortResidualType::kExact,
                                     int taylor_iterations = 2) {
    return new ceres::AutoDiffCostFunction<FlatPortReprojectionCost, 2, 4, 5, 3, 1, 4, 4, 3>(
        new FlatPortReprojectionCost(observed, point_in_board, type, taylor_iterations));
  }

 private:
  Eigen::Vector2d observed_;
  Eigen::Vector3d point_in_board_;
  FlatPortResidualType type_;
  int taylor_iterations_;
};

}  // namespace uwscan
