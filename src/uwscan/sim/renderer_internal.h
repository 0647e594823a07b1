// Private pieces of the Renderer shared by its source files.
#pragma once

#include <array>
#include <vector>

#include "uwscan/sim/parallel.h"
#include "uwscan/sim/renderer.h"

namespace uwscan::sim {

// A laser source's pose and optics for one frame.
struct Renderer::LaserFrame {
  int source = 0;
  Rigid3d camera_from_laser;
  Rigid3d laser_from_camera;
  Eigen::Matrix3d laser_R_camera;
  std::array<double, 4> q_wxyz;  // camera_from_laser rotation for the templated model
  double p1 = 0.0;
  double tan_half_fan = 0.0;
  Optics optics;
};

// Per-frame accumulators (electrons before the pixel gain, R G B).
struct Renderer::Buffers {
  cv::Mat sharp;        // CV_32FC3: direct light, unscattered on the way to the camera
  cv::Mat blurred;      // CV_32FC3: direct light scattered into the small-angle lobe
  cv::Mat back;         // CV_32FC3: backscatter / veiling light
  cv::Mat range;        // CV_32F
  double weight = 1.0;  // of the current pass: 1 / (exposure poses x supersample^2)
  Eigen::Vector2d sub_offset = Eigen::Vector2d::Zero();  // of the current supersampling pass (px)
};

inline double Gaussian(double x, double sigma) {
  constexpr double kInvSqrt2Pi = 0.3989422804014327;
  const double z = x / sigma;
  return kInvSqrt2Pi / sigma * std::exp(-0.5 * z * z);
}

}  // namespace uwscan::sim
