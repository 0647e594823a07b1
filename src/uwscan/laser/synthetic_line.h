// Small synthetic laser-line images with exact ground truth, for unit tests
// and micro-benchmarks of the detector (the full physics is in sim/).
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "uwscan/laser/detector.h"

namespace uwscan::laser {

struct SyntheticLineOptions {
  int width = 320;
  int height = 240;
  ColourLayout layout = ColourLayout::kMono;
  bool sixteen_bit = false;
  // Line centre along each row: u(v) = u0 + slope (v - h/2) + curvature (v - h/2)^2.
  double u0 = 150.3;
  double slope = 0.15;
  double curvature = 0.0;
  double sigma_px = 1.5;
  double amplitude = 0.7;    // peak, fraction of full scale (laser colour)
  double background = 0.15;  // mean scene brightness (LED colour)
  double texture = 0.03;     // standard deviation of smooth random texture
  double noise = 0.008;      // Gaussian read noise, fraction of full scale
  int first_row = 0;         // rows outside [first_row, last_row] have no laser
  int last_row = 1 << 30;
  // Optional painted stripe (scene texture that looks like a line): white paint
  // lit by the LED, so it has the LED's colour.
  bool stripe = false;
  double stripe_u0 = 60.0;
  double stripe_slope = 0.05;
  double stripe_sigma_px = 1.8;
  double stripe_amplitude = 0.5;
  // Optional albedo edge along the line, this far from its centre (px): the
  // surface beyond it reflects albedo_dark of the light (laser and LED)
  // reflected before it.
  bool albedo_edge = false;
  double albedo_edge_offset_px = 0.7;
  double albedo_dark = 0.05;
  // Colours (R, G, B) of the laser and of the LED-lit scene, as seen by the
  // camera's colour filters (crosstalk included).
  cv::Vec3d laser_colour{0.08, 1.0, 0.15};
  cv::Vec3d scene_colour{1.0, 0.35, 0.2};
  unsigned seed = 1;
};

struct SyntheticLine {
  cv::Mat image;
  std::vector<cv::Point2d> truth;  // (u, v) of the line centre on each lit row
};

SyntheticLine RenderSyntheticLine(const SyntheticLineOptions& options);

}  // namespace uwscan::laser
