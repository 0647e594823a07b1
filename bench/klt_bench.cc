// Our KLT (uwscan::vo::TrackLucasKanade) against OpenCV's
// calcOpticalFlowPyrLK on the same 640x480 images and points, one thread
// each (Google Benchmark; items are points). As the feature tracker calls
// them: from a guess at full resolution (the refinement from the anchor,
// the backward check, the forward pass from the prediction), and over
// three levels without one (a track searched again).
#include <benchmark/benchmark.h>

#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>
#include <vector>

#include "uwscan/vo/lucas_kanade.h"

namespace {

constexpr int kWindow = 21;

struct Scene {
  std::vector<cv::Mat> from, to;  // pyramids with our border
  std::vector<cv::Point2f> points, guesses;

  Scene() {
    // Blurred noise (texture at a few pixels' scale), and the same moved
    // by a sub-pixel shift.
    cv::Mat noise(480, 640, CV_32F);
    cv::setRNGSeed(5);
    cv::randn(noise, 0, 60);
    cv::Mat texture;
    cv::GaussianBlur(noise, texture, cv::Size(0, 0), 1.5);
    texture += 128;
    const cv::Mat shift = (cv::Mat_<double>(2, 3) << 1, 0, 0.73, 0, 1, -0.41);
    cv::Mat a, b, moved;
    texture.convertTo(a, CV_8U);
    cv::warpAffine(texture, moved, shift, texture.size(), cv::INTER_CUBIC, cv::BORDER_REFLECT_101);
    moved.convertTo(b, CV_8U);
    const int border = uwscan::vo::LucasKanadeBorderPx(kWindow);
    cv::buildOpticalFlowPyramid(a, from, cv::Size(border, border), 3, false);
    cv::buildOpticalFlowPyramid(b, to, cv::Size(border, border), 3, false);
    for (int y = 30; y < 450; y += 20) {
      for (int x = 30; x < 610; x += 20) {
        points.emplace_back(x + 0.25f, y + 0.5f);
        guesses.emplace_back(x + 0.25f + 1.2f, y + 0.5f - 0.6f);
      }
    }
  }
};

const Scene& TheScene() {
  static const Scene scene;
  return scene;
}

void Ours(benchmark::State& state, int levels, bool from_guess) {
  cv::setNumThreads(1);
  const Scene& scene = TheScene();
  std::vector<cv::Point2f> tracked;
  std::vector<uint8_t> status;
  for (auto _ : state) {
    tracked = scene.guesses;
    uwscan::vo::TrackLucasKanade(scene.from, scene.to, scene.points, &tracked, &status, levels,
                                 from_guess, {});
    benchmark::DoNotOptimize(tracked.data());
  }
  state.SetItemsProcessed(state.iterations() * scene.points.size());
}

void OpenCv(benchmark::State& state, int levels, bool from_guess) {
  cv::setNumThreads(1);
  const Scene& scene = TheScene();
  std::vector<cv::Point2f> tracked;
  std::vector<uint8_t> status;
  std::vector<float> error;
  const cv::TermCriteria criteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 0.01);
  for (auto _ : state) {
    tracked = scene.guesses;
    cv::calcOpticalFlowPyrLK(scene.from, scene.to, scene.points, tracked, status, error,
                             cv::Size(kWindow, kWindow), levels, criteria,
                             from_guess ? cv::OPTFLOW_USE_INITIAL_FLOW : 0);
    benchmark::DoNotOptimize(tracked.data());
  }
  state.SetItemsProcessed(state.iterations() * scene.points.size());
}

}  // namespace

BENCHMARK_CAPTURE(OpenCv, full_resolution_from_guess, 0, true);
BENCHMARK_CAPTURE(Ours, full_resolution_from_guess, 0, true);
BENCHMARK_CAPTURE(OpenCv, three_levels, 3, false);
BENCHMARK_CAPTURE(Ours, three_levels, 3, false);

BENCHMARK_MAIN();
