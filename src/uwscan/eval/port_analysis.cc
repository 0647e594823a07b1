#include "uwscan/eval/port_analysis.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>

#include "uwscan/sensor/pinhole.h"
#include "uwscan/util/error.h"

namespace uwscan {
namespace {

// Pixels of a regular grid over the image, and for each the point where its
// flat-port ray meets the plane z = depth.
struct PlaneSamples {
  std::vector<Eigen::Vector2d> pixels;
  std::vector<Eigen::Vector3d> points;
};

PlaneSamples SamplePlane(const Camera& camera, double depth_m, int step) {
  PlaneSamples samples;
  for (int v = 0; v <= camera.height; v += step) {
    for (int u = 0; u <= camera.width; u += step) {
      const Eigen::Vector2d pixel(std::min<double>(u, camera.width - 1),
                                  std::min<double>(v, camera.height - 1));
      const auto ray = camera.BackProject(pixel);
      if (!ray || !(ray->direction.z() > 1e-9)) continue;
      const double lambda = (depth_m - ray->origin.z()) / ray->direction.z();
      if (!(lambda > 0)) continue;
      samples.pixels.push_back(pixel);
      samples.points.push_back(ray->At(lambda));
    }
  }
  return samples;
}

// Pinhole re-projection residual of a known point (eq. 4.2, 4.8).
struct PinholeResidual {
  PinholeResidual(const Eigen::Vector2d& pixel, const Eigen::Vector3d& point)
      : pixel_(pixel), point_(point) {}
  template <typename T>
  bool operator()(const T* intrinsics, const T* distortion, T* residual) const {
    const T point[3] = {T(point_.x()), T(point_.y()), T(point_.z())};
    T projected[2];
    if (!PinholeModel::Project(intrinsics, distortion, point, projected)) return false;
    residual[0] = projected[0] - pixel_.x();
    residual[1] = projected[1] - pixel_.y();
    return true;
  }
  static ceres::CostFunction* Create(const Eigen::Vector2d& pixel, const Eigen::Vector3d& point) {
    return new ceres::AutoDiffCostFunction<PinholeResidual, 2, 4, 5>(
        new PinholeResidual(pixel, point));
  }
  Eigen::Vector2d pixel_;
  Eigen::Vector3d point_;
};

}  // namespace

void PinholeFitOptions::Check() const {
  UWS_CHECK(std::isfinite(depth_m) && depth_m > 0.05,
            "pinhole fit: depth must be a distance > 0.05 m, got ", depth_m);
  UWS_CHECK(grid_step_px >= 1, "pinhole fit: grid step must be >= 1 px");
}

ErrorStats ComputeErrorStats(std::vector<double> errors) {
  ErrorStats stats;
  stats.count = static_cast<int>(errors.size());
  if (errors.empty()) return stats;
  std::sort(errors.begin(), errors.end());
  const auto quantile = [&](double q) {
    return errors[std::min(errors.size() - 1, static_cast<size_t>(q * (errors.size() - 1) + 0.5))];
  };
  stats.max_px = errors.back();
  stats.median_px = quantile(0.5);
  stats.p95_px = quantile(0.95);
  double sum = 0.0;
  for (double e : errors) sum += e * e;
  stats.rms_px = std::sqrt(sum / errors.size());
  return stats;
}

PinholeFit FitPinholeToFlatPort(const Camera& flatport, const PinholeFitOptions& options) {
  options.Check();
  UWS_CHECK(flatport.IsFlatPort(), "pinhole fit: camera '", flatport.name, "' is not a flat port");
  const PlaneSamples samples = SamplePlane(flatport, options.depth_m, options.grid_step_px);
  UWS_CHECK(samples.pixels.size() >= 20, "pinhole fit: too few image points see the plane");

  PinholeFit fit;
  fit.pinhole = flatport;
  fit.pinhole.model = CameraModelId::kPinhole;
  // Start from the paraxial pinhole: focal length scaled by n_water / n_air.
  const double scale = flatport.port.n_water / flatport.port.n_air;
  fit.pinhole.intrinsics[0] *= scale;
  fit.pinhole.intrinsics[1] *= scale;
  double* intrinsics = fit.pinhole.intrinsics.data();
  double* distortion = fit.pinhole.distortion.data();
  ceres::Problem problem;
  for (size_t i = 0; i < samples.pixels.size(); ++i) {
    problem.AddResidualBlock(PinholeResidual::Create(samples.pixels[i], samples.points[i]), nullptr,
                             intrinsics, distortion);
  }
  ceres::Solver::Options solver_options;
  solver_options.max_num_iterations = 200;
  solver_options.function_tolerance = 1e-14;
  solver_options.gradient_tolerance = 1e-14;
  solver_options.parameter_tolerance = 1e-14;
  solver_options.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  UWS_CHECK(summary.IsSolutionUsable(), "pinhole fit failed: ", summary.message);
  fit.iterations = static_cast<int>(summary.iterations.size());
  fit.at_fit = PinholeErrorAtDepth(flatport, fit.pinhole, options.depth_m, options.grid_step_px);
  return fit;
}

ErrorStats PinholeErrorAtDepth(const Camera& flatport, const Camera& pinhole, double depth_m,
                               int grid_step_px) {
  const PlaneSamples samples = SamplePlane(flatport, depth_m, grid_step_px);
  std::vector<double> errors;
  errors.reserve(samples.pixels.size());
  for (size_t i = 0; i < samples.pixels.size(); ++i) {
    const auto projected = pinhole.Project(samples.points[i], ProjectionMethod::kPinhole);
    if (projected) errors.push_back((*projected - samples.pixels[i]).norm());
  }
  return ComputeErrorStats(std::move(errors));
}

double OptimalAirGap(const FlatPort& port, double air_angle_rad) {
  const double sine = std::sin(air_angle_rad);
  const auto slope = [&](double n_to) {
    const double s = port.n_air / n_to * sine;
    return s / std::sqrt(1.0 - s * s);
  };
  const double m_air = slope(port.n_air);
  const double m_glass = slope(port.n_glass);
  const double m_water = slope(port.n_water);
  UWS_CHECK(std::abs(m_air - m_water) > 1e-12, "optimal d_air: undefined for n_water = n_air");
  return port.d_glass * (m_water - m_glass) / (m_air - m_water);  // eq. 4.27
}

}  // namespace uwscan
