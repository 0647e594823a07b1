// Pinhole camera with Brown distortion in OpenCV's convention (thesis §4.2,
// eqs. 4.2 and 4.8). Parameter groups are kept separate so that Ceres can hold
// any of them fixed:
//   intrinsics[4] = fx, fy, cx, cy
//   distortion[5] = k1, k2, p1, p2, k3
// "Normalised" coordinates are the undistorted (x, y) on the plane z = 1.
#pragma once

#include <cmath>

#include "uwscan/sensor/scalar.h"

namespace uwscan {

struct PinholeModel {
  static constexpr int kNumIntrinsics = 4;
  static constexpr int kNumDistortion = 5;

  // Brown distortion of normalised coordinates (OpenCV order k1 k2 p1 p2 k3).
  template <typename T>
  static void Distort(const T* distortion, const T& x, const T& y, T* xd, T* yd) {
    const T& k1 = distortion[0];
    const T& k2 = distortion[1];
    const T& p1 = distortion[2];
    const T& p2 = distortion[3];
    const T& k3 = distortion[4];
    const T x2 = x * x;
    const T y2 = y * y;
    const T xy = x * y;
    const T r2 = x2 + y2;
    const T radial = T(1) + r2 * (k1 + r2 * (k2 + r2 * k3));
    *xd = x * radial + T(2) * p1 * xy + p2 * (r2 + T(2) * x2);
    *yd = y * radial + p1 * (r2 + T(2) * y2) + T(2) * p2 * xy;
  }

  // Jacobian of Distort at (x, y), row-major 2x2.
  template <typename T>
  static void DistortJacobian(const T* distortion, const T& x, const T& y, T* jacobian) {
    const T& k1 = distortion[0];
    const T& k2 = distortion[1];
    const T& p1 = distortion[2];
    const T& p2 = distortion[3];
    const T& k3 = distortion[4];
    const T r2 = x * x + y * y;
    const T radial = T(1) + r2 * (k1 + r2 * (k2 + r2 * k3));
    const T dradial_dr2 = k1 + r2 * (T(2) * k2 + T(3) * k3 * r2);
    jacobian[0] = radial + T(2) * x * x * dradial_dr2 + T(2) * p1 * y + T(6) * p2 * x;
    jacobian[1] = T(2) * x * y * dradial_dr2 + T(2) * p1 * x + T(2) * p2 * y;
    jacobian[2] = T(2) * x * y * dradial_dr2 + T(2) * p1 * x + T(2) * p2 * y;
    jacobian[3] = radial + T(2) * y * y * dradial_dr2 + T(6) * p1 * y + T(2) * p2 * x;
  }

  // True if the radial distortion r (1 + k1 r^2 + k2 r^4 + k3 r^6) still
  // grows all the way from the centre out to r^2 = r2. Past its first fold
  // it turns back and maps rays far outside the field of view into the
  // image (with the tank camera's k1 -0.037, k2 0.0002 a ray 79 degrees off
  // the axis lands at the image's corner, one 80 degrees off at its
  // centre), so nothing there is imaged. The tangential terms are small
  // and left out.
  template <typename T>
  static bool BeforeRadialFold(const T* distortion, double r2) {
    const double k1 = ScalarOf(distortion[0]), k2 = ScalarOf(distortion[1]),
                 k3 = ScalarOf(distortion[4]);
    // d/dr of r * radial as a polynomial in s = r^2; it is 1 at the centre.
    const auto slope = [&](double s) {
      return 1.0 + s * (3.0 * k1 + s * (5.0 * k2 + s * 7.0 * k3));
    };
    if (!(slope(r2) > 0.0)) return false;
    // Its lowest values between lie where its derivative 3 k1 + 10 k2 s +
    // 21 k3 s^2 vanishes.
    const double a = 21.0 * k3, b = 10.0 * k2, c = 3.0 * k1;
    double turns[2];
    int n = 0;
    if (a == 0.0) {
      if (b != 0.0) turns[n++] = -c / b;
    } else if (const double discriminant = b * b - 4.0 * a * c; discriminant >= 0.0) {
      const double q = -0.5 * (b + std::copysign(std::sqrt(discriminant), b));
      turns[n++] = q / a;
      if (q != 0.0) turns[n++] = c / q;
    }
    for (int i = 0; i < n; ++i) {
      if (turns[i] > 0.0 && turns[i] < r2 && !(slope(turns[i]) > 0.0)) return false;
    }
    return true;
  }

  // Normalised coordinates -> pixel. False past the distortion's fold
  // (BeforeRadialFold).
  template <typename T>
  [[nodiscard]] static bool NormalizedToImage(const T* intrinsics, const T* distortion, const T& x,
                                              const T& y, T* pixel) {
    const double xs = ScalarOf(x), ys = ScalarOf(y);
    if (!BeforeRadialFold(distortion, xs * xs + ys * ys)) return false;
    T xd, yd;
    Distort(distortion, x, y, &xd, &yd);
    pixel[0] = intrinsics[0] * xd + intrinsics[2];
    pixel[1] = intrinsics[1] * yd + intrinsics[3];
    return true;
  }

  // Camera-frame point -> pixel. False for points on or behind the camera
  // plane, and for those past the distortion's fold.
  template <typename T>
  static bool Project(const T* intrinsics, const T* distortion, const T* point, T* pixel) {
    if (!(ScalarOf(point[2]) > 0.0)) return false;
    return NormalizedToImage(intrinsics, distortion, point[0] / point[2], point[1] / point[2],
                             pixel);
  }

  // Pixel -> normalised coordinates: inverts the distortion by damped Newton
  // on the values, then one Newton step in T so that Jets get exact
  // derivatives. False if the inversion does not converge (pixel outside the
  // region where the distortion is invertible).
  template <typename T>
  static bool ImageToNormalized(const T* intrinsics, const T* distortion, const T& u, const T& v,
                                T* x, T* y) {
    const T xd = (u - intrinsics[2]) / intrinsics[0];
    const T yd = (v - intrinsics[3]) / intrinsics[1];
    double dist[kNumDistortion];
    for (int i = 0; i < kNumDistortion; ++i) dist[i] = ScalarOf(distortion[i]);
    double xs, ys;
    if (!UndistortValues(dist, ScalarOf(xd), ScalarOf(yd), &xs, &ys)) return false;
    // One Newton step in T around the converged value.
    const T xt(xs), yt(ys);
    T xc, yc, jac[4];
    Distort(distortion, xt, yt, &xc, &yc);
    DistortJacobian(distortion, xt, yt, jac);
    const T rx = xd - xc;
    const T ry = yd - yc;
    const T det = jac[0] * jac[3] - jac[1] * jac[2];
    *x = xt + (jac[3] * rx - jac[1] * ry) / det;
    *y = yt + (jac[0] * ry - jac[2] * rx) / det;
    return true;
  }

  // Camera ray (unit direction) of a pixel.
  template <typename T>
  static bool BackProject(const T* intrinsics, const T* distortion, const T& u, const T& v,
                          T* direction) {
    T x, y;
    if (!ImageToNormalized(intrinsics, distortion, u, v, &x, &y)) return false;
    using std::sqrt;
    const T norm = sqrt(x * x + y * y + T(1));
    direction[0] = x / norm;
    direction[1] = y / norm;
    direction[2] = T(1) / norm;
    return true;
  }

  // Solves Distort(x, y) = (xd, yd) on doubles.
  static bool UndistortValues(const double* distortion, double xd, double yd, double* x,
                              double* y) {
    bool no_distortion = true;
    for (int i = 0; i < kNumDistortion; ++i) no_distortion &= distortion[i] == 0.0;
    if (no_distortion) {
      *x = xd;
      *y = yd;
      return true;
    }
    double xs = xd, ys = yd;
    double cx, cy;
    Distort(distortion, xs, ys, &cx, &cy);
    double error = std::hypot(cx - xd, cy - yd);
    for (int iteration = 0; iteration < 100; ++iteration) {
      if (error < 1e-15 * (1.0 + std::hypot(xd, yd))) break;
      double jac[4];
      DistortJacobian(distortion, xs, ys, jac);
      const double det = jac[0] * jac[3] - jac[1] * jac[2];
      if (!(std::abs(det) > 1e-12)) return false;
      const double rx = xd - cx, ry = yd - cy;
      double step_x = (jac[3] * rx - jac[1] * ry) / det;
      double step_y = (jac[0] * ry - jac[2] * rx) / det;
      // Damping: halve the step until the residual decreases.
      bool improved = false;
      for (int halving = 0; halving < 30; ++halving) {
        const double nx = xs + step_x, ny = ys + step_y;
        double nxd, nyd;
        Distort(distortion, nx, ny, &nxd, &nyd);
        const double new_error = std::hypot(nxd - xd, nyd - yd);
        if (new_error < error) {
          xs = nx, ys = ny, cx = nxd, cy = nyd, error = new_error;
          improved = true;
          break;
        }
        step_x *= 0.5;
        step_y *= 0.5;
      }
      if (!improved) break;
    }
    if (!(error < 1e-10 * (1.0 + std::hypot(xd, yd))) || !std::isfinite(xs) || !std::isfinite(ys)) {
      return false;
    }
    // A solution where the distortion folds over, or beyond its first fold
    // where it rises again, is not the physical one: the pixel is outside
    // the invertible region.
    double jac[4];
    DistortJacobian(distortion, xs, ys, jac);
    if (!(jac[0] * jac[3] - jac[1] * jac[2] > 0.0) ||
        !BeforeRadialFold(distortion, xs * xs + ys * ys)) {
      return false;
    }
    *x = xs;
    *y = ys;
    return true;
  }
};

}  // namespace uwscan
