// Flat-port refractive camera (thesis §4.2, Tab. 4.4): a pinhole + Brown
// lens behind a planar glass window. Parameter groups:
//   intrinsics[4], distortion[5]  as in PinholeModel
//   normal[3]   port normal in the camera frame, camera -> water (normalised here)
//   port[5]     = d_air, d_glass, n_air, n_glass, n_water
// Inner glass surface {X : n.X = d_air}, outer {X : n.X = d_air + d_glass}.
//
// All three functions are templates on the scalar so Ceres Jets flow through.
#pragma once

#include <algorithm>
#include <cmath>
#include <utility>

#include "uwscan/sensor/pinhole.h"
#include "uwscan/sensor/scalar.h"

namespace uwscan {

enum class TaylorVariant {
  // Eq. 4.24 as printed: the perpendicular slope derivative taken at the
  // port axis, m'(0) = n_a/n_i, scaled by n_z (eq. 4.26). Converges linearly
  // in the direction across the plane of refraction.
  kThesisAxis,
  // The same first-order expansion (eq. 4.23) with the perpendicular slope
  // derivative taken at the current ray v0 instead of at the axis; identical
  // on the axis, exact to first order everywhere, so both directions converge
  // quadratically. The default.
  kCentred,
};

struct FlatPortModel {
  static constexpr int kNumPort = 5;

  // Why a projection failed; kOk when it did not.
  enum class Status { kOk, kBehindPort, kTotalReflection, kDegenerate, kNoConvergence };

  // --- Back-projection (eqs. 4.9-4.10) -------------------------------------
  // Pixel -> ray in water: `origin` on the outer glass surface, unit
  // `direction`. Fails if the air ray does not reach the port or is totally
  // reflected.
  template <typename T>
  static bool BackProject(const T* intrinsics, const T* distortion, const T* normal_in,
                          const T* port, const T& u, const T& v, T* origin, T* direction) {
    T x, y;
    if (!PinholeModel::ImageToNormalized(intrinsics, distortion, u, v, &x, &y)) return false;
    const T ray[3] = {x, y, T(1)};
    return RefractRay(normal_in, port, ray, origin, direction);
  }

  // Normalised air ray (any length, z > 0) -> ray in water.
  template <typename T>
  static bool RefractRay(const T* normal_in, const T* port, const T* ray, T* origin, T* direction) {
    using std::sqrt;
    T n[3];
    if (!Normalize(normal_in, n)) return false;
    const T& d_air = port[0];
    const T& d_glass = port[1];
    const T& n_air = port[2];
    const T& n_glass = port[3];
    const T& n_water = port[4];
    const T ray_norm = sqrt(Dot(ray, ray));
    T air[3] = {ray[0] / ray_norm, ray[1] / ray_norm, ray[2] / ray_norm};
    const T cos_air = Dot(n, air);
    if (!(ScalarOf(cos_air) > 1e-12)) return false;  // parallel to or away from the port
    // Entry point on the inner surface.
    T entry[3];
    for (int i = 0; i < 3; ++i) entry[i] = air[i] * (d_air / cos_air);
    // Vector Snell's law: the tangential part scales by n1/n2 (eq. 4.9).
    T glass[3];
    if (!Refract(n, air, n_air / n_glass, glass)) return false;
    const T cos_glass = Dot(n, glass);
    for (int i = 0; i < 3; ++i) origin[i] = entry[i] + glass[i] * (d_glass / cos_glass);
    return Refract(n, glass, n_glass / n_water, direction);  // eq. 4.10
  }

  // --- Exact forward projection --------------------------------------------
  // Solves the refraction equation in the plane of refraction (Fig. 4.7,
  // eq. 4.19 with the true slopes): find s = sin(alpha_air) with
  //   d_a tan(a_a) + d_g tan(a_g) + d_w tan(a_w) = L,  sin(a_i) = (n_a/n_i) s,
  // where L is the point's distance from the port axis and d_w its distance
  // from the outer surface. f(s) is increasing and convex on [0, s_max), so
  // safeguarded Newton converges to machine precision.
  template <typename T>
  static bool ProjectExact(const T* intrinsics, const T* distortion, const T* normal_in,
                           const T* port, const T* point, T* pixel, Status* status = nullptr) {
    T air[3];
    const Status result = ExactAirRay(normal_in, port, point, air);
    if (status) *status = result;
    if (result != Status::kOk) return false;
    return PinholeModel::NormalizedToImage(intrinsics, distortion, air[0] / air[2], air[1] / air[2],
                                           pixel);
  }

  // The unit ray in air (camera frame) whose refracted path hits `point`.
  template <typename T>
  static Status ExactAirRay(const T* normal_in, const T* port, const T* point, T* air) {
    using std::sqrt;
    T n[3];
    if (!Normalize(normal_in, n)) return Status::kDegenerate;
    const T& d_air = port[0];
    const T& d_glass = port[1];
    const T axial = Dot(n, point);
    const T d_water = axial - d_air - d_glass;
    if (!(ScalarOf(d_water) > 0.0)) return Status::kBehindPort;
    T lateral[3];
    for (int i = 0; i < 3; ++i) lateral[i] = point[i] - axial * n[i];
    const double lateral_value = std::sqrt(ScalarOf(Dot(lateral, lateral)));
    if (!(lateral_value > 1e-14 * std::abs(ScalarOf(axial)))) {
      // On the port axis the ray runs along the normal. Use the paraxial
      // limit (tan a_i = (n_a/n_i) tan a_a) in vector form, exact to first
      // order in the lateral offset, so that Jets keep their derivatives
      // here instead of seeing a constant ray.
      using std::sqrt;
      const T paraxial = d_air + d_glass * port[2] / port[3] + d_water * port[2] / port[4];
      T norm2 = T(0);
      for (int i = 0; i < 3; ++i) {
        air[i] = n[i] + lateral[i] / paraxial;
        norm2 += air[i] * air[i];
      }
      const T norm = sqrt(norm2);
      for (int i = 0; i < 3; ++i) air[i] /= norm;
      return ScalarOf(air[2]) > 1e-12 ? Status::kOk : Status::kDegenerate;
    }
    const T lateral_norm = sqrt(Dot(lateral, lateral));
    const double values[6] = {ScalarOf(d_air),
                              ScalarOf(d_glass),
                              ScalarOf(d_water),
                              ScalarOf(port[2]) / ScalarOf(port[3]),
                              ScalarOf(port[2]) / ScalarOf(port[4]),
                              lateral_value};
    double s = 0.0;
    if (!SolveSine(values, &s)) return Status::kTotalReflection;
    // One Newton step in T: exact derivatives by the implicit function theorem.
    const T ratio_glass = port[2] / port[3];
    const T ratio_water = port[2] / port[4];
    const T st(s);
    T f = -lateral_norm, df = T(0);
    AddSlope(d_air, T(1), st, &f, &df);
    AddSlope(d_glass, ratio_glass, st, &f, &df);
    AddSlope(d_water, ratio_water, st, &f, &df);
    const T sine = st - f / df;
    const T cosine = sqrt(T(1) - sine * sine);
    for (int i = 0; i < 3; ++i) air[i] = cosine * n[i] + sine * lateral[i] / lateral_norm;
    return ScalarOf(air[2]) > 1e-12 ? Status::kOk : Status::kDegenerate;
  }

  // --- Bracketed forward projection (doubles) ------------------------------
  // For callers that need a point's pixel only to tell which side of a line
  // it falls on (binning into cells), at half the exact projection's cost.
  // Newton steps on the same f(s) as SolveSine, from the start that neglects
  // the port's thickness, until |f(s)| / f'(0) < `tolerance`: f is convex
  // and increasing on [0, s_max), so f' >= f'(0) there and that quotient
  // bounds |s - s*|. Returns the unit air rays at s -/+ the bound; the exact
  // ray lies between them in their plane (through the port axis), so its
  // normalised image point lies on the segment between theirs. False where
  // only the exact solver can tell (on the axis, behind the port, near total
  // reflection, too many steps).
  static bool BracketAirRay(const double* normal_in, const double* port, const double* point,
                            double tolerance, double* air_low, double* air_high) {
    double n[3];
    if (!Normalize(normal_in, n)) return false;
    const double d[3] = {port[0], port[1], Dot(n, point) - port[0] - port[1]};
    if (!(d[2] > 0.0)) return false;
    const double r[3] = {1.0, port[2] / port[3], port[2] / port[4]};
    double lateral[3];
    for (int i = 0; i < 3; ++i) lateral[i] = point[i] - (d[2] + d[0] + d[1]) * n[i];
    const double lateral_norm = std::sqrt(Dot(lateral, lateral));
    if (!(lateral_norm > 1e-9 * (d[2] + d[0] + d[1]))) return false;
    double s_max = 1.0;
    for (int i = 0; i < 3; ++i) {
      if (d[i] > 0.0) s_max = std::min(s_max, 1.0 / r[i]);
    }
    const double min_slope = d[0] + d[1] * r[1] + d[2] * r[2];  // f'(0)
    // The water ray straight from the centre: f(s) > 0 there, and Newton
    // from the right of the root of a convex increasing f stays right of it.
    const double tan_water = lateral_norm / d[2];
    double s = tan_water / std::sqrt(1.0 + tan_water * tan_water) / r[2];
    double bound = 0.0;
    for (int step = 0;; ++step) {
      if (!(s > 0.0 && s < s_max) || step == 8) return false;
      double f = -lateral_norm, df = 0.0;
      for (int i = 0; i < 3; ++i) AddSlope(d[i], r[i], s, &f, &df);
      bound = std::abs(f) / min_slope;
      if (bound < tolerance) break;
      s -= f / df;
    }
    const double s_low = s - bound, s_high = s + bound;
    if (!(s_low > 0.0 && s_high < s_max * (1.0 - 1e-9))) return false;
    for (auto [sine, air] : {std::pair{s_low, air_low}, std::pair{s_high, air_high}}) {
      const double cosine = std::sqrt(1.0 - sine * sine);
      for (int i = 0; i < 3; ++i) air[i] = cosine * n[i] + sine * lateral[i] / lateral_norm;
      if (!(air[2] > 1e-9)) return false;
    }
    return true;
  }

  // --- Taylor forward projection (eqs. 4.13-4.26) --------------------------
  // Starts from the normalised coordinates `start` (e.g. from a measured
  // pixel or from PinholeStart) and applies `iterations` first-order steps.
  template <typename T>
  static bool ProjectTaylor(const T* intrinsics, const T* distortion, const T* normal_in,
                            const T* port, const T* point, const T* start, int iterations, T* pixel,
                            TaylorVariant variant = TaylorVariant::kCentred) {
    T n[3];
    if (!Normalize(normal_in, n)) return false;
    T x = start[0], y = start[1];
    for (int k = 0; k < iterations; ++k) {
      if (!TaylorStep(n, port, point, variant, &x, &y)) return false;
    }
    return PinholeModel::NormalizedToImage(intrinsics, distortion, x, y, pixel);
  }

  // Taylor projection centred at a measured pixel (as in calibration, §4.4).
  template <typename T>
  static bool ProjectTaylorFromPixel(const T* intrinsics, const T* distortion, const T* normal,
                                     const T* port, const T* point, const T* start_pixel,
                                     int iterations, T* pixel,
                                     TaylorVariant variant = TaylorVariant::kCentred) {
    T start[2] = {T(0.0), T(0.0)};
    if (!PinholeModel::ImageToNormalized(intrinsics, distortion, start_pixel[0], start_pixel[1],
                                         &start[0], &start[1])) {
      return false;
    }
    return ProjectTaylor(intrinsics, distortion, normal, port, point, start, iterations, pixel,
                         variant);
  }

  // Paraxial start for the Taylor iteration: the pinhole that the port
  // becomes for rays close to its axis (tan a_i ~ (n_a/n_i) tan a_a), in
  // normalised coordinates. Exact on the axis, cheap as a pinhole.
  template <typename T>
  static bool PinholeStart(const T* normal_in, const T* port, const T* point, T* start) {
    T n[3];
    if (!Normalize(normal_in, n)) return false;
    const T axial = Dot(n, point);
    const T d_water = axial - port[0] - port[1];
    if (!(ScalarOf(d_water) > 0.0)) return false;
    // Virtual point on the axis-aligned pinhole: shrink the axial distance.
    const T virtual_axial = port[0] + port[1] * port[2] / port[3] + d_water * port[2] / port[4];
    T virtual_point[3];
    for (int i = 0; i < 3; ++i) virtual_point[i] = point[i] + (virtual_axial - axial) * n[i];
    if (!(ScalarOf(virtual_point[2]) > 0.0)) return false;
    start[0] = virtual_point[0] / virtual_point[2];
    start[1] = virtual_point[1] / virtual_point[2];
    return true;
  }

  // One Taylor step on normalised coordinates (x, y) towards `point`.
  template <typename T>
  static bool TaylorStep(const T* n, const T* port, const T* point, TaylorVariant variant, T* x,
                         T* y) {
    using std::sqrt;
    const T& d_air = port[0];
    const T& d_glass = port[1];
    const T ratio_glass = port[2] / port[3];
    const T ratio_water = port[2] / port[4];
    const T axial = Dot(n, point);
    const T d_water = axial - d_air - d_glass;
    if (!(ScalarOf(d_water) > 0.0) || !(ScalarOf(n[2]) > 1e-12)) return false;
    // v_par: direction in the image plane from the axis point n/n_z to v0 (eq. 4.13).
    const T v0[3] = {*x, *y, T(1)};
    T w[2] = {*x - n[0] / n[2], *y - n[1] / n[2]};
    if (!(std::hypot(ScalarOf(w[0]), ScalarOf(w[1])) > 1e-13)) {
      // v0 on the axis: the plane of refraction is the one through the point.
      w[0] = point[0] / point[2] - n[0] / n[2];
      w[1] = point[1] / point[2] - n[1] / n[2];
      if (!(std::hypot(ScalarOf(w[0]), ScalarOf(w[1])) > 1e-13)) return true;  // point on axis
    }
    const T w_norm = sqrt(w[0] * w[0] + w[1] * w[1]);
    const T v_par[3] = {w[0] / w_norm, w[1] / w_norm, T(0)};
    const T v_perp[3] = {-v_par[1], v_par[0], T(0)};  // eq. 4.14
    // Basis of the plane of refraction (eq. 4.15).
    T e_perp[3], e_par[3];
    Cross(n, v_par, e_perp);
    const T e_perp_norm = sqrt(Dot(e_perp, e_perp));
    for (int i = 0; i < 3; ++i) e_perp[i] /= e_perp_norm;
    Cross(e_perp, n, e_par);
    // Slopes of v0 in the three media (eqs. 4.16-4.18).
    const T c0 = Dot(n, v0);
    const T s0 = Dot(e_par, v0);
    const T v0_norm = sqrt(Dot(v0, v0));
    const T sin_air = s0 / v0_norm;
    const T cos_air = c0 / v0_norm;
    const T sin_glass = ratio_glass * sin_air;
    const T sin_water = ratio_water * sin_air;
    if (!(std::abs(ScalarOf(sin_glass)) < 1.0) || !(std::abs(ScalarOf(sin_water)) < 1.0)) {
      return false;
    }
    const T cos_glass = sqrt(T(1) - sin_glass * sin_glass);
    const T cos_water = sqrt(T(1) - sin_water * sin_water);
    // Lateral offset predicted for v0 (eq. 4.19) and its derivative along
    // v_par: d tan(a_i) / d tan(a_a) = (n_a/n_i) cos^3(a_a) / cos^3(a_i).
    const T g = d_air * s0 / c0 + d_glass * sin_glass / cos_glass + d_water * sin_water / cos_water;
    const T dtan_air = (Dot(e_par, v_par) * c0 - s0 * Dot(n, v_par)) / (c0 * c0);
    const T cos3_air = cos_air * cos_air * cos_air;
    const T dg =
        dtan_air * (d_air + d_glass * ratio_glass * cos3_air / (cos_glass * cos_glass * cos_glass) +
                    d_water * ratio_water * cos3_air / (cos_water * cos_water * cos_water));
    const T delta_par = (Dot(e_par, point) - g) / dg;  // eq. 4.24, first line
    // Across the plane of refraction (eq. 4.24, second line; eq. 4.26).
    T delta_perp;
    if (variant == TaylorVariant::kThesisAxis) {
      const T dperp = d_air + d_glass * ratio_glass + d_water * ratio_water;
      delta_perp = Dot(e_perp, point) / dperp * n[2];
    } else {
      const T dperp =
          Dot(e_perp, v_perp) / v0_norm *
          (d_air / cos_air + d_glass * ratio_glass / cos_glass + d_water * ratio_water / cos_water);
      delta_perp = Dot(e_perp, point) / dperp;
    }
    *x = *x + delta_par * v_par[0] + delta_perp * v_perp[0];
    *y = *y + delta_par * v_par[1] + delta_perp * v_perp[1];
    return true;
  }

  // --- Small helpers ---------------------------------------------------------
  template <typename T>
  static T Dot(const T* a, const T* b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  }
  template <typename T>
  static void Cross(const T* a, const T* b, T* c) {
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
  }
  template <typename T>
  static bool Normalize(const T* in, T* out) {
    using std::sqrt;
    const T norm = sqrt(Dot(in, in));
    if (!(ScalarOf(norm) > 0.0)) return false;
    for (int i = 0; i < 3; ++i) out[i] = in[i] / norm;
    return true;
  }

  // Refracts unit `in` at a surface with unit normal `n` (pointing along the
  // travel direction); `ratio` = n_from / n_to. False on total reflection.
  template <typename T>
  static bool Refract(const T* n, const T* in, const T& ratio, T* out) {
    using std::sqrt;
    const T cos_in = Dot(n, in);
    T tangential[3];
    for (int i = 0; i < 3; ++i) tangential[i] = ratio * (in[i] - cos_in * n[i]);
    const T sin2_out = Dot(tangential, tangential);
    if (!(ScalarOf(sin2_out) < 1.0)) return false;
    const T cos_out = sqrt(T(1) - sin2_out);
    for (int i = 0; i < 3; ++i) out[i] = tangential[i] + cos_out * n[i];
    return true;
  }

  // f += d * tan(asin(ratio * s)), df += d/ds of that.
  template <typename T>
  static void AddSlope(const T& d, const T& ratio, const T& s, T* f, T* df) {
    using std::sqrt;
    const T sine = ratio * s;
    const T cos2 = T(1) - sine * sine;
    const T cosine = sqrt(cos2);
    *f += d * sine / cosine;
    *df += d * ratio / (cos2 * cosine);
  }

  // Solves sum_i d_i tan(asin(r_i s)) = L for s on doubles, to within
  // about kPolishedStep^2 of s and of its distance to s_max: ExactAirRay's
  // one Newton step after it brings s to machine precision.
  // values = {d_air, d_glass, d_water, r_glass, r_water, L}.
  static constexpr double kPolishedStep = 1e-7;
  static bool SolveSine(const double* values, double* s_out) {
    const double d[3] = {values[0], values[1], values[2]};
    const double r[3] = {1.0, values[3], values[4]};
    const double lateral = values[5];
    double s_max = 1.0;
    for (int i = 0; i < 3; ++i) {
      if (d[i] > 0.0) s_max = std::min(s_max, 1.0 / r[i]);
    }
    auto evaluate = [&](double s, double* f, double* df) {
      *f = -lateral;
      *df = 0.0;
      for (int i = 0; i < 3; ++i) AddSlope(d[i], r[i], s, f, df);
    };
    // Paraxial start: tan a_i ~ r_i tan a_a.
    const double t0 = lateral / (d[0] + d[1] * r[1] + d[2] * r[2]);
    double s = std::min(t0 / std::sqrt(1.0 + t0 * t0), 0.5 * s_max);
    double lo = 0.0, hi = s_max;
    for (int iteration = 0; iteration < 200; ++iteration) {
      double f, df;
      evaluate(s, &f, &df);
      if (f > 0.0)
        hi = s;
      else
        lo = s;
      double next = s - f / df;
      const bool newton = next > lo && next < hi;
      if (!newton) next = 0.5 * (lo + hi);
      // A Newton step this small leaves an error of order its square over
      // the distance to the pole at s_max (f's curvature grows as a ray
      // nears grazing), which the caller's Newton step (ExactAirRay's, in
      // T) squares again: no need to confirm the last bit here.
      if ((newton && std::abs(next - s) <= kPolishedStep * std::min(s, s_max - s)) ||
          std::abs(next - s) <= 4e-16 * std::max(s, 1e-300) || hi - lo <= 4e-16 * hi) {
        s = next;
        break;
      }
      s = next;
    }
    // A point that no ray below the critical angle reaches.
    if (!(s < s_max * (1.0 - 1e-12))) return false;
    *s_out = s;
    return true;
  }
};

}  // namespace uwscan
