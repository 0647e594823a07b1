// Private pieces of the Renderer shared by its source files.
#pragma once

#include <array>
#include <functional>
#include <thread>
#include <vector>

#include "uwscan/sim/renderer.h"

namespace uwscan::sim {

// A laser source's pose and optics for one frame.
struct Renderer::LaserFrame {
  int source = 0;
  Rigid3d camera_from_laser;
  Rigid3d laser_from_camera;
  std::array<double, 4> q_wxyz;  // camera_from_laser rotation for the templated model
  double p1 = 0.0;
  double tan_half_fan = 0.0;
  Optics optics;
};

// Per-frame accumulators (electrons before the pixel gain, R G B).
struct Renderer::Buffers {
  cv::Mat sharp;    // CV_32FC3: direct light, unscattered on the way to the camera
  cv::Mat blurred;  // CV_32FC3: direct light scattered into the small-angle lobe
  cv::Mat back;     // CV_32FC3: backscatter / veiling light
  cv::Mat range;    // CV_32F
  double weight = 1.0;  // 1 / number of exposure poses
};

// Runs fn(y) for every row on `threads` threads (interleaved blocks of rows).
inline void ParallelRows(int rows, int threads, const std::function<void(int)>& fn) {
  constexpr int kBlock = 8;
  if (threads <= 1 || rows < 2 * kBlock) {
    for (int y = 0; y < rows; ++y) fn(y);
    return;
  }
  std::vector<std::thread> workers;
  for (int t = 0; t < threads; ++t) {
    workers.emplace_back([&, t] {
      for (int start = t * kBlock; start < rows; start += threads * kBlock) {
        for (int y = start; y < std::min(rows, start + kBlock); ++y) fn(y);
      }
    });
  }
  for (auto& worker : workers) worker.join();
}

inline double Gaussian(double x, double sigma) {
  constexpr double kInvSqrt2Pi = 0.3989422804014327;
  const double z = x / sigma;
  return kInvSqrt2Pi / sigma * std::exp(-0.5 * z * z);
}

}  // namespace uwscan::sim
