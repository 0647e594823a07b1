// Micro-benchmarks of the camera models (Google Benchmark). The user-facing
// figures come from `uwscan bench projection`; this is for profiling.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "uwscan/sensor/camera.h"

namespace {

std::vector<Eigen::Vector3d> RandomPoints(const uwscan::Camera& camera, int count) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, camera.width - 1), v(0, camera.height - 1),
      depth(0.5, 10.0);
  std::vector<Eigen::Vector3d> points;
  while (static_cast<int>(points.size()) < count) {
    const auto ray = camera.BackProject(Eigen::Vector2d(u(rng), v(rng)));
    if (ray) points.push_back(ray->At(depth(rng)));
  }
  return points;
}

void Project(benchmark::State& state, uwscan::ProjectionMethod method, int iterations) {
  const uwscan::Camera camera = uwscan::Camera::Flat3();
  const auto points = RandomPoints(camera, 4096);
  size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(camera.Project(points[i++ & 4095], method, iterations));
  }
  state.SetItemsProcessed(state.iterations());
}

void BackProject(benchmark::State& state) {
  const uwscan::Camera camera = uwscan::Camera::Flat3();
  size_t i = 0;
  for (auto _ : state) {
    const Eigen::Vector2d pixel((i * 37) % 1280, (i * 17) % 960);
    benchmark::DoNotOptimize(camera.BackProject(pixel));
    ++i;
  }
  state.SetItemsProcessed(state.iterations());
}

}  // namespace

BENCHMARK_CAPTURE(Project, pinhole, uwscan::ProjectionMethod::kPinhole, 0);
BENCHMARK_CAPTURE(Project, taylor2, uwscan::ProjectionMethod::kTaylor, 2);
BENCHMARK_CAPTURE(Project, exact, uwscan::ProjectionMethod::kExact, 0);
BENCHMARK(BackProject);
BENCHMARK_MAIN();
