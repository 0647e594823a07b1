// Test helper: renders what a downward-looking (flat-port or pinhole) camera
// sees of a textured sea floor, by casting each pixel's ray
// (Camera::BackProject) onto the terrain z = relief(x, y) and looking up a
// procedural texture with bilinear interpolation. Stands in for the image
// simulator in the VO tests and benchmarks; ground truth comes for free.
#pragma once

#include <opencv2/core.hpp>
#include <optional>
#include <vector>

#include "uwscan/geometry/rigid3d.h"
#include "uwscan/sensor/camera.h"

namespace uwscan::vo::testing {

struct TerrainOptions {
  double x_min_m = -3.0, x_max_m = 25.0;  // textured extent (world x, y)
  double y_min_m = -4.0, y_max_m = 4.0;
  double texel_m = 0.004;
  double relief_amplitude_m = 0.15;  // z = A sin(2 pi x / L) cos(2 pi y / L)
  double relief_wavelength_m = 3.0;
  unsigned seed = 7;
};

// World: z up, sea floor near z = 0.
class TexturedTerrain {
 public:
  explicit TexturedTerrain(const TerrainOptions& options = {});
  double Height(double x, double y) const;
  // Intersects a world ray with the terrain (fixed-point iteration).
  std::optional<Eigen::Vector3d> Intersect(const Eigen::Vector3d& origin,
                                           const Eigen::Vector3d& direction) const;
  const cv::Mat& texture() const { return texture_; }  // CV_32F, 0..255
  const TerrainOptions& options() const { return options_; }

 private:
  TerrainOptions options_;
  cv::Mat texture_;
};

struct RenderOptions {
  double contrast = 1.0;     // medium: texture contrast multiplier (1 = clear)
  double backscatter = 0.0;  // medium: grey level added everywhere
  double noise_sigma = 0.0;  // additive Gaussian noise (grey levels)
  unsigned noise_seed = 1;
  // Optional bright laser line: image column u = laser_column_px + slope*(v - h/2).
  double laser_column_px = -1.0;  // < 0: no laser
  double laser_slope = 0.05;
  double laser_width_px = 2.0;
};

class PlaneRenderer {
 public:
  PlaneRenderer(const Camera& camera, const TexturedTerrain& terrain);
  // 8-bit grey image of the terrain seen from world_from_camera.
  cv::Mat Render(const Rigid3d& world_from_camera, const RenderOptions& options = {}) const;
  // Mask (CV_8U, 255 = laser) matching RenderOptions' laser line, dilated by margin_px.
  cv::Mat LaserMask(const RenderOptions& options, double margin_px = 3.0) const;
  // World point seen at a pixel (for ground-truth flow).
  std::optional<Eigen::Vector3d> PointAt(const Rigid3d& world_from_camera,
                                         const Eigen::Vector2d& pixel) const;
  const Camera& camera() const { return camera_; }

 private:
  Camera camera_;
  const TexturedTerrain& terrain_;
  std::vector<std::optional<Ray>> rays_;  // per pixel, camera frame
};

using uwscan::ScaledCamera;  // sensor/camera.h

// A camera looking straight down (optical axis -z_world, image x along world
// x) at position (x, y, altitude) with small yaw/roll wobble.
Rigid3d DownwardPose(const Eigen::Vector3d& position, double yaw_rad = 0.0, double roll_rad = 0.0,
                     double pitch_rad = 0.0);

}  // namespace uwscan::vo::testing

namespace uwscan::vo::testing {

// A survey line along world x (camera tilted by `tilt_rad` to look ahead) at `altitude_m` above the
// mean floor, with a gentle sideways sway, yaw and roll wobble (world_from_camera per frame).
std::vector<Rigid3d> TransectPoses(int frames, double length_m, double altitude_m,
                                   double sway_m = 0.1, double wobble_rad = 0.03,
                                   double tilt_rad = 0.0);

}  // namespace uwscan::vo::testing
