// Line laser projector (thesis §4.3, Tab. 4.7, eq. 4.30): an inverse line
// camera with canonical intrinsics. In the laser frame the x axis runs along
// the line and z is the projection direction; the light sheet is the x-z
// plane bent by the tangential coefficient p1 into the cone
//   y / z = p1 (x / z)^2   (eq. 4.30 with d = 0).
// Parameters: camera_from_laser rotation q[4] = (w, x, y, z), translation
// t[3], and p1.
#pragma once

#include <ceres/rotation.h>

#include <cmath>

#include "uwscan/sensor/scalar.h"

namespace uwscan {

struct LineProjectorModel {
  // The point in the laser frame: R^T (X - t).
  template <typename T>
  static void CameraToLaser(const T* camera_from_laser_q, const T* camera_from_laser_t,
                            const T* point_in_camera, T* point_in_laser) {
    const T inverse_q[4] = {camera_from_laser_q[0], -camera_from_laser_q[1],
                            -camera_from_laser_q[2], -camera_from_laser_q[3]};
    const T shifted[3] = {point_in_camera[0] - camera_from_laser_t[0],
                          point_in_camera[1] - camera_from_laser_t[1],
                          point_in_camera[2] - camera_from_laser_t[2]};
    ceres::QuaternionRotatePoint(inverse_q, shifted, point_in_laser);
  }

  // Residual of eq. 4.30: d = x_y/x_z - p1 (x_x/x_z)^2, in canonical
  // projector units (tangent of the angle off the sheet). False for points
  // behind the projector.
  template <typename T>
  static bool SheetResidual(const T* camera_from_laser_q, const T* camera_from_laser_t, const T& p1,
                            const T* point_in_camera, T* residual) {
    T p[3];
    CameraToLaser(camera_from_laser_q, camera_from_laser_t, point_in_camera, p);
    if (!(ScalarOf(p[2]) > 0.0)) return false;
    const T x = p[0] / p[2];
    residual[0] = p[1] / p[2] - p1 * x * x;
    return true;
  }

  // Intersects the ray origin + lambda * direction (camera frame, lambda > 0)
  // with the sheet. For p1 = 0 this is eq. 5.2; otherwise the quadratic
  //   (a_y + l b_y)(a_z + l b_z) = p1 (a_x + l b_x)^2
  // in laser coordinates, taking the root in front of the projector that
  // continues the planar solution as p1 -> 0. False if the ray misses.
  template <typename T>
  static bool Triangulate(const T* camera_from_laser_q, const T* camera_from_laser_t, const T& p1,
                          const T* origin, const T* direction, T* point) {
    using std::abs;
    using std::sqrt;
    T a[3], b[3];
    CameraToLaser(camera_from_laser_q, camera_from_laser_t, origin, a);
    const T inverse_q[4] = {camera_from_laser_q[0], -camera_from_laser_q[1],
                            -camera_from_laser_q[2], -camera_from_laser_q[3]};
    ceres::QuaternionRotatePoint(inverse_q, direction, b);

    const double plane_lambda = -ScalarOf(a[1]) / ScalarOf(b[1]);
    T lambda;
    if (ScalarOf(p1) == 0.0) {
      if (!(std::abs(ScalarOf(b[1])) > 1e-15)) return false;  // ray parallel to the sheet
      lambda = -a[1] / b[1];
    } else {
      const T qa = b[1] * b[2] - p1 * b[0] * b[0];
      const T qb = a[1] * b[2] + a[2] * b[1] - T(2) * p1 * a[0] * b[0];
      const T qc = a[1] * a[2] - p1 * a[0] * a[0];
      // Roots by the numerically stable formula; pick the valid one nearest to
      // the planar solution.
      T roots[2];
      int count = 0;
      if (std::abs(ScalarOf(qa)) < 1e-300) {
        if (std::abs(ScalarOf(qb)) < 1e-300) return false;
        roots[count++] = -qc / qb;
      } else {
        const T disc = qb * qb - T(4) * qa * qc;
        if (ScalarOf(disc) < 0.0) return false;
        const T sq = sqrt(disc);
        const T q = ScalarOf(qb) >= 0.0 ? T(-0.5) * (qb + sq) : T(-0.5) * (qb - sq);
        if (std::abs(ScalarOf(q)) > 0.0) {
          roots[count++] = q / qa;
          roots[count++] = qc / q;
        } else {
          roots[count++] = T(0);
        }
      }
      int best = -1;
      double best_distance = 0.0;
      for (int i = 0; i < count; ++i) {
        const double l = ScalarOf(roots[i]);
        if (!(l > 0.0) || !(ScalarOf(a[2]) + l * ScalarOf(b[2]) > 0.0)) continue;
        const double distance = std::isfinite(plane_lambda) ? std::abs(l - plane_lambda) : l;
        if (best < 0 || distance < best_distance) best = i, best_distance = distance;
      }
      if (best < 0) return false;
      lambda = roots[best];
    }
    if (!(ScalarOf(lambda) > 0.0)) return false;
    if (!(ScalarOf(a[2]) + ScalarOf(lambda) * ScalarOf(b[2]) > 0.0)) return false;  // behind laser
    for (int i = 0; i < 3; ++i) point[i] = origin[i] + lambda * direction[i];
    return true;
  }
};

}  // namespace uwscan
