#include "uwscan/vo/testing/plane_renderer.h"

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <random>

#include "uwscan/util/error.h"

namespace uwscan::vo::testing {

TexturedTerrain::TexturedTerrain(const TerrainOptions& options) : options_(options) {
  const int width = int(std::ceil((options.x_max_m - options.x_min_m) / options.texel_m));
  const int height = int(std::ceil((options.y_max_m - options.y_min_m) / options.texel_m));
  UWS_CHECK(width > 8 && height > 8 && size_t(width) * height < 200'000'000ull,
            "TexturedTerrain: bad extent or texel size");
  cv::RNG rng(options.seed);
  texture_ = cv::Mat(height, width, CV_32F, cv::Scalar(0));
  // Smoothed random noise at several scales (sediment of all grain sizes).
  for (int scale : {3, 7, 16, 40, 100}) {
    cv::Mat small(std::max(2, height / scale), std::max(2, width / scale), CV_32F);
    rng.fill(small, cv::RNG::UNIFORM, -1.0, 1.0);
    cv::Mat big;
    cv::resize(small, big, texture_.size(), 0, 0, cv::INTER_CUBIC);
    texture_ += big * (scale <= 7 ? 0.6 : 1.0);
  }
  // Blobs (stones, shells).
  const int blobs = int(double(width) * height / 4000.0);
  for (int i = 0; i < blobs; ++i) {
    const cv::Point c(rng.uniform(0, width), rng.uniform(0, height));
    const int r = int(std::exp(rng.uniform(std::log(2.0), std::log(25.0))));
    cv::circle(texture_, c, r, cv::Scalar(rng.uniform(-2.0, 2.0)), -1, cv::LINE_AA);
  }
  cv::GaussianBlur(texture_, texture_, cv::Size(0, 0), 0.8);
  double lo, hi;
  cv::minMaxLoc(texture_, &lo, &hi);
  texture_ = (texture_ - lo) * (215.0 / (hi - lo)) + 20.0;
}

double TexturedTerrain::Height(double x, double y) const {
  const double k = 2.0 * M_PI / options_.relief_wavelength_m;
  return options_.relief_amplitude_m * std::sin(k * x) * std::cos(k * y);
}

std::optional<Eigen::Vector3d> TexturedTerrain::Intersect(const Eigen::Vector3d& origin,
                                                          const Eigen::Vector3d& direction) const {
  if (direction.z() > -1e-6) return std::nullopt;  // must go down
  double z = 0.0;
  Eigen::Vector3d p;
  for (int k = 0; k < 8; ++k) {
    const double lambda = (z - origin.z()) / direction.z();
    if (lambda <= 0) return std::nullopt;
    p = origin + lambda * direction;
    const double next = Height(p.x(), p.y());
    const bool converged = std::abs(next - z) < 1e-7;
    z = next;
    if (converged || options_.relief_amplitude_m == 0.0) break;
  }
  p.z() = z;
  return p;
}

PlaneRenderer::PlaneRenderer(const Camera& camera, const TexturedTerrain& terrain)
    : camera_(camera), terrain_(terrain) {
  rays_.resize(size_t(camera.width) * camera.height);
  for (int v = 0; v < camera.height; ++v) {
    for (int u = 0; u < camera.width; ++u) {
      rays_[size_t(v) * camera.width + u] = camera.BackProject(Eigen::Vector2d(u, v));
    }
  }
}

std::optional<Eigen::Vector3d> PlaneRenderer::PointAt(const Rigid3d& world_from_camera,
                                                      const Eigen::Vector2d& pixel) const {
  const std::optional<Ray> ray = camera_.BackProject(pixel);
  if (!ray) return std::nullopt;
  return terrain_.Intersect(world_from_camera * ray->origin,
                            world_from_camera.rotation * ray->direction);
}

cv::Mat PlaneRenderer::Render(const Rigid3d& world_from_camera,
                              const RenderOptions& options) const {
  const TerrainOptions& t = terrain_.options();
  cv::Mat map_x(camera_.height, camera_.width, CV_32F),
      map_y(camera_.height, camera_.width, CV_32F);
  const Eigen::Matrix3d rotation = world_from_camera.RotationMatrix();
  for (int v = 0; v < camera_.height; ++v) {
    float* mx = map_x.ptr<float>(v);
    float* my = map_y.ptr<float>(v);
    for (int u = 0; u < camera_.width; ++u) {
      const auto& ray = rays_[size_t(v) * camera_.width + u];
      mx[u] = my[u] = -1e6f;
      if (!ray) continue;
      const auto p = terrain_.Intersect(world_from_camera * ray->origin, rotation * ray->direction);
      if (!p) continue;
      mx[u] = float((p->x() - t.x_min_m) / t.texel_m);
      my[u] = float((p->y() - t.y_min_m) / t.texel_m);
    }
  }
  cv::Mat sampled;
  cv::remap(terrain_.texture(), sampled, map_x, map_y, cv::INTER_LINEAR, cv::BORDER_CONSTANT,
            cv::Scalar(0));
  sampled = sampled * options.contrast + options.backscatter;
  if (options.noise_sigma > 0) {
    cv::Mat noise(sampled.size(), CV_32F);
    cv::RNG rng(options.noise_seed);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, options.noise_sigma);
    sampled += noise;
  }
  if (options.laser_column_px >= 0) {
    for (int v = 0; v < sampled.rows; ++v) {
      const double center =
          options.laser_column_px + options.laser_slope * (v - sampled.rows / 2.0);
      float* row = sampled.ptr<float>(v);
      for (int u = std::max(0, int(center - 4 * options.laser_width_px));
           u < std::min(sampled.cols, int(center + 4 * options.laser_width_px) + 1); ++u) {
        const double d = (u - center) / options.laser_width_px;
        row[u] += float(220.0 * std::exp(-0.5 * d * d));
      }
    }
  }
  cv::Mat image;
  sampled.convertTo(image, CV_8U);  // saturates
  return image;
}

cv::Mat PlaneRenderer::LaserMask(const RenderOptions& options, double margin_px) const {
  cv::Mat mask(camera_.height, camera_.width, CV_8U, cv::Scalar(0));
  if (options.laser_column_px < 0) return mask;
  const double half = 3.0 * options.laser_width_px + margin_px;
  for (int v = 0; v < mask.rows; ++v) {
    const double center = options.laser_column_px + options.laser_slope * (v - mask.rows / 2.0);
    for (int u = std::max(0, int(center - half)); u <= std::min(mask.cols - 1, int(center + half));
         ++u) {
      mask.at<uint8_t>(v, u) = 255;
    }
  }
  return mask;
}

Rigid3d DownwardPose(const Eigen::Vector3d& position, double yaw_rad, double roll_rad,
                     double pitch_rad) {
  // Camera z = -world z, camera x = world x, camera y = -world y.
  Eigen::Matrix3d base;
  base << 1, 0, 0, 0, -1, 0, 0, 0, -1;
  const Eigen::Matrix3d wobble = (Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()) *
                                  Eigen::AngleAxisd(roll_rad, Eigen::Vector3d::UnitX()) *
                                  Eigen::AngleAxisd(pitch_rad, Eigen::Vector3d::UnitY()))
                                     .toRotationMatrix();
  return Rigid3d(Eigen::Quaterniond(wobble * base), position);
}

}  // namespace uwscan::vo::testing

namespace uwscan::vo::testing {

std::vector<Rigid3d> TransectPoses(int frames, double length_m, double altitude_m, double sway_m,
                                   double wobble_rad, double tilt_rad) {
  std::vector<Rigid3d> poses;
  for (int i = 0; i < frames; ++i) {
    const double s = frames > 1 ? double(i) / (frames - 1) : 0.0;
    const double x = s * length_m;
    const double phase = 2.0 * M_PI * x / 4.0;
    poses.push_back(DownwardPose(
        Eigen::Vector3d(x, sway_m * std::sin(phase), altitude_m + 0.1 * std::sin(0.7 * phase)),
        wobble_rad * std::sin(0.5 * phase), wobble_rad * std::cos(0.9 * phase),
        0.5 * wobble_rad * std::sin(1.3 * phase) - tilt_rad));
  }
  return poses;
}

}  // namespace uwscan::vo::testing
