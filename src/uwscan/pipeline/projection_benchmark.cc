#include "uwscan/pipeline/projection_benchmark.h"

#include <chrono>
#include <random>

#include "uwscan/sensor/camera.h"
#include "uwscan/util/error.h"

namespace uwscan {
namespace {

// Keeps the compiler from discarding the projections.
volatile double g_sink = 0.0;

struct Method {
  std::string name;
  ProjectionMethod method;
  int iterations;
};

}  // namespace

void ProjectionBenchmarkOptions::Check() const {
  UWS_CHECK(points >= 1000, "bench projection: --points must be >= 1000");
  UWS_CHECK(repetitions >= 1, "bench projection: --repetitions must be >= 1");
}

std::vector<ProjectionRate> RunProjectionBenchmark(const ProjectionBenchmarkOptions& options) {
  options.Check();
  const std::vector<std::pair<std::string, Camera>> cameras = {
      {"Flat1", Camera::Flat1()}, {"Flat2", Camera::Flat2()}, {"Flat3", Camera::Flat3()}};
  const std::vector<Method> methods = {{"pinhole", ProjectionMethod::kPinhole, 0},
                                       {"taylor1", ProjectionMethod::kTaylor, 1},
                                       {"taylor2", ProjectionMethod::kTaylor, 2},
                                       {"taylor3", ProjectionMethod::kTaylor, 3},
                                       {"exact", ProjectionMethod::kExact, 0}};
  std::vector<ProjectionRate> rates;
  for (const auto& [name, camera] : cameras) {
    std::mt19937 rng(options.seed);
    std::uniform_real_distribution<double> u(0.0, camera.width - 1.0);
    std::uniform_real_distribution<double> v(0.0, camera.height - 1.0);
    std::uniform_real_distribution<double> depth(0.5, 10.0);
    std::vector<Eigen::Vector3d> points;
    points.reserve(options.points);
    while (static_cast<int>(points.size()) < options.points) {
      const auto ray = camera.BackProject(Eigen::Vector2d(u(rng), v(rng)));
      if (ray) points.push_back(ray->At(depth(rng)));
    }
    std::vector<Eigen::Vector2d> exact(points.size());
    for (size_t i = 0; i < points.size(); ++i) exact[i] = *camera.Project(points[i]);

    for (const auto& method : methods) {
      double best_seconds = 1e30;
      double max_error = 0.0;
      for (int repetition = 0; repetition < options.repetitions; ++repetition) {
        double sum = 0.0;
        const auto start = std::chrono::steady_clock::now();
        for (const auto& point : points) {
          const auto pixel = camera.Project(point, method.method, method.iterations);
          if (pixel) sum += pixel->x();
        }
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        g_sink = g_sink + sum;
        best_seconds = std::min(best_seconds, seconds);
      }
      for (size_t i = 0; i < points.size(); ++i) {
        const auto pixel = camera.Project(points[i], method.method, method.iterations);
        if (pixel) max_error = std::max(max_error, (*pixel - exact[i]).norm());
      }
      rates.push_back({name, method.name, points.size() / best_seconds, max_error});
    }
  }
  return rates;
}

nlohmann::json ProjectionBenchmarkToJson(const std::vector<ProjectionRate>& rates,
                                         const ProjectionBenchmarkOptions& options) {
  nlohmann::json json;
  json["benchmark"] = "projection";
  json["points_per_camera"] = options.points;
  json["repetitions"] = options.repetitions;
  json["threads"] = 1;
  json["results"] = nlohmann::json::array();
  for (const auto& rate : rates) {
    double pinhole_rate = 0.0;
    for (const auto& other : rates) {
      if (other.camera == rate.camera && other.method == "pinhole") pinhole_rate = other.points_per_second;
    }
    json["results"].push_back({{"camera", rate.camera},
                               {"method", rate.method},
                               {"points_per_second", rate.points_per_second},
                               {"slowdown_vs_pinhole", pinhole_rate / rate.points_per_second},
                               {"max_error_vs_exact_px", rate.max_error_px}});
  }
  return json;
}

}  // namespace uwscan
