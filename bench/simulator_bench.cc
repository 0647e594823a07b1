// Frames per second of the simulator (docs/BENCHMARKS.md, "Simulator"):
// tank-target frames rendered in memory (Render: ray tracing, scattering,
// sensor) and the same plus laser ground truth and PNG encoding as
// `uwscan simulate` writes them. Construction (per-pixel ray tables) is
// reported separately.
//   build/bin/simulator_bench --benchmark_min_time=2
#include <benchmark/benchmark.h>

#include <opencv2/imgcodecs.hpp>

#include "uwscan/sim/renderer.h"
#include "uwscan/sim/scenario.h"

namespace {

using namespace uwscan::sim;

Scenario TankTarget(int width, int threads = 2) {
  ScenarioOptions options;
  options.width = width;
  options.height = width * 3 / 4;
  options.frames = 1000;
  options.threads = threads;
  return MakeScenario("tank-target", options);
}

// range(1) = threads; with one thread the CPU time is the whole work,
// independent of other load on the machine.
void BM_RenderFrame(benchmark::State& state) {
  const Scenario scenario =
      TankTarget(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  const Renderer renderer(scenario.config);
  const Trajectory trajectory(scenario.motion);
  int frame = 0;
  for (auto _ : state) {
    const RenderedFrame rendered = renderer.Render(scenario.FrameAt(trajectory, frame++ % 1000));
    benchmark::DoNotOptimize(rendered.image.data);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_RenderFrame)
    ->ArgsProduct({{320, 640, 1280}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_FrameWithTruthAndPng(benchmark::State& state) {
  const Scenario scenario = TankTarget(static_cast<int>(state.range(0)));
  const Renderer renderer(scenario.config);
  const Trajectory trajectory(scenario.motion);
  int frame = 0;
  for (auto _ : state) {
    const FrameState frame_state = scenario.FrameAt(trajectory, frame++ % 1000);
    const RenderedFrame rendered = renderer.Render(frame_state);
    const auto truth = renderer.LaserGroundTruth(frame_state);
    std::vector<uchar> png;
    cv::imencode(".png", rendered.image, png, {cv::IMWRITE_PNG_COMPRESSION, 3});
    benchmark::DoNotOptimize(png.data());
    benchmark::DoNotOptimize(truth.data());
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_FrameWithTruthAndPng)
    ->Arg(320)
    ->Arg(640)
    ->Arg(1280)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_RendererSetup(benchmark::State& state) {
  const Scenario scenario = TankTarget(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    const Renderer renderer(scenario.config);
    benchmark::DoNotOptimize(&renderer);
  }
}
BENCHMARK(BM_RendererSetup)->Arg(1280)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
