#include "uwscan/eval/cloud_metrics.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>
#include <random>

#include "uwscan/geometry/fits.h"
#include "uwscan/util/error.h"
#include "uwscan/util/json.h"
#include "uwscan/util/statistics.h"

namespace uwscan {
namespace {

// Relative distance errors between random pairs of points at least 5 cm
// apart (true distance), in percent.
void DistanceErrors(const std::vector<Eigen::Vector3d>& reconstructed,
                    const std::vector<Eigen::Vector3d>& truth, unsigned seed,
                    SurfaceAccuracy* out) {
  if (reconstructed.size() < 2) return;
  std::mt19937 rng(seed);
  std::uniform_int_distribution<size_t> pick(0, reconstructed.size() - 1);
  std::vector<double> errors;
  for (int attempt = 0; attempt < 20000 && errors.size() < 5000; ++attempt) {
    const size_t a = pick(rng), b = pick(rng);
    const double d_true = (truth[a] - truth[b]).norm();
    if (d_true < 0.05) continue;
    errors.push_back(100.0 * std::abs((reconstructed[a] - reconstructed[b]).norm() - d_true) /
                     d_true);
  }
  if (errors.empty()) return;
  double sum = 0.0;
  for (double e : errors) sum += e;
  out->distance_error_mean_pct = sum / errors.size();
  out->distance_error_median_pct = Median(errors);
  out->distance_pairs = static_cast<int>(errors.size());
}

// Robust refit (see SurfaceAccuracy::robust_fit_rms_m). `residuals` fits
// the shape to its first argument and returns the residuals of the second
// under that fit, or nothing if the shape cannot be fitted; with `robust`
// (the rounds that find the outliers) under a robust loss where the fit is
// iterative and could be pulled into another minimum by them, as a
// cylinder's is (kRobustLossScaleM); the final fit is plain least squares.
using FitResiduals = std::function<std::optional<std::vector<double>>(
    const std::vector<Eigen::Vector3d>& fit_to, const std::vector<Eigen::Vector3d>& evaluate,
    bool robust)>;
constexpr double kOutlierGateM = 0.005;  // the gate's floor
constexpr double kRobustLossScaleM = kOutlierGateM;

void RobustFit(const std::vector<Eigen::Vector3d>& points, const FitResiduals& residuals,
               SurfaceAccuracy* out) {
  std::vector<Eigen::Vector3d> kept = points;
  for (int round = 0; round < 2; ++round) {
    const auto all = residuals(kept, points, /*robust=*/true);
    if (!all) return;
    std::vector<double> magnitudes;
    for (double r : *all) magnitudes.push_back(std::abs(r));
    const double gate = std::max(5.0 * 1.4826 * Median(magnitudes), kOutlierGateM);
    kept.clear();
    for (size_t i = 0; i < points.size(); ++i)
      if (magnitudes[i] <= gate) kept.push_back(points[i]);
    if (static_cast<long>(kept.size()) < SurfaceAccuracy::kMinPoints) return;
  }
  const auto final_residuals = residuals(kept, kept, /*robust=*/false);
  if (!final_residuals) return;
  out->robust_fitted = true;
  out->robust_fit_rms_m = Rms(*final_residuals);
  out->robust_outliers = static_cast<long>(points.size() - kept.size());
}

}  // namespace

nlohmann::json SurfaceAccuracy::ToJson() const {
  const bool distances = distance_pairs > 0;
  return {{"name", name},
          {"type", type},
          {"points", points},
          {"fit_rms_mm", ValueOrNull(fitted, fit_rms_m * 1e3)},
          {"fit_max_abs_mm", ValueOrNull(fitted, fit_max_abs_m * 1e3)},
          {"robust_fit_rms_mm", ValueOrNull(robust_fitted, robust_fit_rms_m * 1e3)},
          {"robust_outliers", ValueOrNull(robust_fitted, robust_outliers)},
          {"point_error_rms_mm", ValueOrNull(Measured(), point_error_rms_m * 1e3)},
          {"distance_error_mean_pct", ValueOrNull(distances, distance_error_mean_pct)},
          {"distance_error_median_pct", ValueOrNull(distances, distance_error_median_pct)},
          {"distance_pairs", distance_pairs}};
}

nlohmann::json CloudAccuracy::ToJson() const {
  nlohmann::json json = {
      {"points", points},
      {"matched", matched},
      {"point_error_rms_mm", ValueOrNull(matched > 0, point_error_rms_m * 1e3)},
      {"point_error_median_mm", ValueOrNull(matched > 0, point_error_median_m * 1e3)}};
  json["surfaces"] = nlohmann::json::array();
  for (const auto& s : surfaces) json["surfaces"].push_back(s.ToJson());
  return json;
}

const SurfaceAccuracy* CloudAccuracy::Surface(const std::string& name) const {
  for (const auto& s : surfaces) {
    if (s.name == name) return &s;
  }
  return nullptr;
}

CloudAccuracy EvaluateCloud(const std::vector<CloudPoint>& cloud,
                            const std::map<int, Rigid3d>& estimated,
                            const std::map<int, Rigid3d>& truth, const Camera& camera,
                            const sim::Scene& scene,
                            const std::map<int, const Camera*>& frame_cameras, unsigned seed) {
  // The first frame both trajectories know anchors the estimated world.
  std::optional<Rigid3d> true_from_estimated;
  for (const auto& [frame, pose] : estimated) {
    const auto it = truth.find(frame);
    if (it != truth.end()) {
      true_from_estimated = it->second * pose.Inverse();
      break;
    }
  }
  UWS_CHECK(true_from_estimated.has_value(), "evaluation: the trajectories share no frame");
  CloudAccuracy accuracy;
  accuracy.points = static_cast<long>(cloud.size());
  std::vector<std::vector<Eigen::Vector3d>> reconstructed(scene.surfaces.size()),
      true_points(scene.surfaces.size());
  std::vector<double> errors;
  for (const auto& point : cloud) {
    const auto est = estimated.find(point.frame);
    const auto tru = truth.find(point.frame);
    if (est == estimated.end() || tru == truth.end()) continue;
    const auto other = frame_cameras.find(point.frame);
    const Camera& taken_by = other == frame_cameras.end() ? camera : *other->second;
    const auto pixel = taken_by.Project(est->second.Inverse() * point.position);
    if (!pixel) continue;
    const auto ray = taken_by.BackProject(*pixel);
    if (!ray) continue;
    const Rigid3d& world_from_camera = tru->second;
    const auto hit = scene.Intersect(world_from_camera * ray->origin,
                                     world_from_camera.rotation * ray->direction);
    if (!hit) continue;
    const Eigen::Vector3d in_true_world = *true_from_estimated * point.position;
    ++accuracy.matched;
    errors.push_back((in_true_world - hit->point_world).norm());
    reconstructed[hit->surface].push_back(in_true_world);
    true_points[hit->surface].push_back(hit->point_world);
  }
  accuracy.point_error_rms_m = Rms(errors);
  accuracy.point_error_median_m = Median(errors);
  for (size_t s = 0; s < scene.surfaces.size(); ++s) {
    const auto& surface = scene.surfaces[s];
    SurfaceAccuracy result;
    result.name = surface.name;
    result.type = sim::SurfaceTypeName(surface.type);
    result.points = static_cast<long>(reconstructed[s].size());
    if (!result.Measured()) {
      accuracy.surfaces.push_back(result);
      continue;
    }
    std::vector<double> point_errors;
    for (size_t i = 0; i < reconstructed[s].size(); ++i) {
      point_errors.push_back((reconstructed[s][i] - true_points[s][i]).norm());
    }
    result.point_error_rms_m = Rms(point_errors);
    if (surface.type == sim::SurfaceType::kPlane) {
      if (const auto plane = FitPlane(reconstructed[s])) {
        result.fitted = true;
        result.fit_rms_m = plane->rms;
        result.fit_max_abs_m = plane->max_abs;
      }
      RobustFit(
          reconstructed[s],
          [](const std::vector<Eigen::Vector3d>& fit_to,
             const std::vector<Eigen::Vector3d>& evaluate,
             bool /*robust: the plane's fit has one minimum*/)
              -> std::optional<std::vector<double>> {
            const auto plane = FitPlane(fit_to);
            if (!plane) return std::nullopt;
            std::vector<double> r;
            for (const auto& p : evaluate) r.push_back(plane->SignedDistance(p));
            return r;
          },
          &result);
      DistanceErrors(reconstructed[s], true_points[s], seed, &result);
    } else if (surface.type == sim::SurfaceType::kCylinder) {
      const Eigen::Vector3d axis = surface.world_from_surface.rotation * Eigen::Vector3d::UnitZ();
      Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
      for (const auto& p : reconstructed[s]) centroid += p;
      centroid /= reconstructed[s].size();
      const Eigen::Vector3d towards = surface.world_from_surface.translation - centroid;
      const Eigen::Vector3d towards_axis = towards - towards.dot(axis) * axis;
      if (const auto cylinder = FitCylinder(reconstructed[s], axis, surface.radius, towards_axis)) {
        result.fitted = true;
        result.fit_rms_m = cylinder->rms;
        for (const auto& p : reconstructed[s]) {
          result.fit_max_abs_m = std::max(result.fit_max_abs_m, std::abs(cylinder->Residual(p)));
        }
      }
      RobustFit(
          reconstructed[s],
          [&](const std::vector<Eigen::Vector3d>& fit_to,
              const std::vector<Eigen::Vector3d>& evaluate,
              bool robust) -> std::optional<std::vector<double>> {
            const auto cylinder = FitCylinder(fit_to, axis, surface.radius, towards_axis,
                                              robust ? kRobustLossScaleM : 0.0);
            if (!cylinder) return std::nullopt;
            std::vector<double> r;
            for (const auto& p : evaluate) r.push_back(cylinder->Residual(p));
            return r;
          },
          &result);
    }
    accuracy.surfaces.push_back(result);
  }
  return accuracy;
}

}  // namespace uwscan
