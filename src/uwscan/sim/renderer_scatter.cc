// Volume terms of eq. 2.6 that are smooth across the image: backscatter of
// the flood lights (single scattering along each camera ray, computed on a
// coarse pixel grid and interpolated) and the forward-scatter blur E_f.
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "uwscan/sim/renderer.h"
#include "uwscan/sim/renderer_internal.h"

namespace uwscan::sim {

void Renderer::AddFloodBackscatter(const Rigid3d& world_from_camera, Buffers* buffers) const {
  const Medium& medium = config_.medium;
  const RenderOptions& options = config_.render;
  const int samples = options.backscatter_samples;
  const int step = BackscatterStep();
  cv::Mat coarse = cv::Mat::zeros(coarse_rows_, coarse_cols_, CV_32FC3);
  const Eigen::Matrix3d world_R_camera = world_from_camera.RotationMatrix();

  ParallelRows(coarse_rows_, options.threads, [&](int j) {
    for (int i = 0; i < coarse_cols_; ++i) {
      const PixelRay& ray = coarse_rays_[static_cast<size_t>(j) * coarse_cols_ + i];
      if (ray.direction.squaredNorm() == 0) continue;
      const Eigen::Vector3d origin = ray.origin.cast<double>(),
                            direction = ray.direction.cast<double>();
      const auto hit = config_.scene.Intersect(
          world_from_camera * origin, world_R_camera * direction, 1e-9, options.max_range_m);
      const double length = hit ? hit->lambda : options.max_range_m;
      Eigen::Vector3d electrons = Eigen::Vector3d::Zero();
      for (size_t f = 0; f < config_.floods.size(); ++f) {
        const FloodLight& flood = config_.floods[f];
        const Optics& optics = flood_optics_[f];
        const double b = optics.scattering;
        if (b <= 0 || flood.power_w <= 0) continue;
        const double k = optics.forward;
        const Eigen::Vector3d axis = flood.camera_from_light.rotation * Eigen::Vector3d::UnitZ();
        double radiance = 0.0;
        // Samples denser near the camera, where backscatter concentrates:
        // s = L u^2, ds = 2 L u du.
        for (int n = 0; n < samples; ++n) {
          const double u = (n + 0.5) / samples;
          const double s = length * u * u;
          const double ds = 2 * length * u / samples;
          const Eigen::Vector3d to_sample =
              origin + s * direction - flood.camera_from_light.translation;
          const double distance = std::max(to_sample.norm(), 1e-3);
          const Eigen::Vector3d unit = to_sample / distance;
          const double intensity = flood.Intensity(axis.dot(unit));
          if (intensity <= 0) continue;
          const double irradiance = intensity / (distance * distance) * std::exp(-k * distance);
          radiance += b * medium.Phase(-unit.dot(direction)) * irradiance * std::exp(-k * s) * ds;
        }
        electrons += radiance * optics.electrons_per_radiance * optics.response;
      }
      coarse.at<cv::Vec3f>(j, i) = cv::Vec3f(electrons[0], electrons[1], electrons[2]);
    }
  });

  const float weight = static_cast<float>(buffers->weight);
  for (int y = 0; y < height_; ++y) {
    const int j0 = std::min(y / step, coarse_rows_ - 2 < 0 ? 0 : coarse_rows_ - 2);
    const int j1 = std::min(j0 + 1, coarse_rows_ - 1);
    const float fy = std::clamp(static_cast<float>(y - j0 * step) / step, 0.0f, 1.0f);
    cv::Vec3f* row = buffers->back.ptr<cv::Vec3f>(y);
    for (int x = 0; x < width_; ++x) {
      const int i0 = std::min(x / step, coarse_cols_ - 2 < 0 ? 0 : coarse_cols_ - 2);
      const int i1 = std::min(i0 + 1, coarse_cols_ - 1);
      const float fx = std::clamp(static_cast<float>(x - i0 * step) / step, 0.0f, 1.0f);
      const cv::Vec3f value =
          (1 - fy) * ((1 - fx) * coarse.at<cv::Vec3f>(j0, i0) + fx * coarse.at<cv::Vec3f>(j0, i1)) +
          fy * ((1 - fx) * coarse.at<cv::Vec3f>(j1, i0) + fx * coarse.at<cv::Vec3f>(j1, i1));
      row[x] += weight * value;
    }
  }
}

namespace {

// Gaussian blur of `sigma` px, done at a reduced resolution for wide kernels.
cv::Mat BlurAtSigma(const cv::Mat& image, double sigma) {
  int factor = 1;
  while (sigma / (2 * factor) >= 3.0) factor *= 2;
  if (factor == 1) {
    cv::Mat out;
    cv::GaussianBlur(image, out, cv::Size(0, 0), sigma, sigma, cv::BORDER_REFLECT);
    return out;
  }
  cv::Mat small, blurred, out;
  cv::resize(image, small,
             cv::Size((image.cols + factor - 1) / factor, (image.rows + factor - 1) / factor), 0, 0,
             cv::INTER_AREA);
  // Box averaging over `factor` px adds variance factor^2 / 12.
  const double residual =
      std::sqrt(std::max(sigma * sigma - factor * factor / 12.0, 0.25 * factor * factor));
  cv::GaussianBlur(small, blurred, cv::Size(0, 0), residual / factor, residual / factor,
                   cv::BORDER_REFLECT);
  cv::resize(blurred, out, image.size(), 0, 0, cv::INTER_LINEAR);
  return out;
}

}  // namespace

void Renderer::AddForwardScatter(Buffers* buffers) const {
  // Angular spread of the small-angle lobe grows with the number of
  // scattering events (~ b r): sigma = f theta sqrt((1 + b r) / 3) px.
  const Medium& medium = config_.medium;
  double max_value = 0;
  cv::minMaxLoc(buffers->blurred.reshape(1), nullptr, &max_value);
  if (max_value <= 0) return;
  const double b = medium.Scattering(530.0);
  const double base = camera().intrinsics[0] * medium.forward_angle_rad;
  if (base <= 0) {
    buffers->sharp += buffers->blurred;
    buffers->blurred.setTo(0);
    return;
  }
  cv::Mat sigma(height_, width_, CV_32F);
  double sigma_min = 1e30, sigma_max = 0;
  for (int y = 0; y < height_; ++y) {
    const float* range = buffers->range.ptr<float>(y);
    float* out = sigma.ptr<float>(y);
    for (int x = 0; x < width_; ++x) {
      out[x] = static_cast<float>(base * std::sqrt((1 + b * range[x]) / 3));
      sigma_min = std::min<double>(sigma_min, out[x]);
      sigma_max = std::max<double>(sigma_max, out[x]);
    }
  }
  sigma_min = std::max(sigma_min, 0.5);
  const int levels =
      1 + static_cast<int>(std::ceil(std::log2(std::max(sigma_max / sigma_min, 1.0))));
  std::vector<cv::Mat> blurred(levels);
  for (int l = 0; l < levels; ++l)
    blurred[l] = BlurAtSigma(buffers->blurred, sigma_min * std::ldexp(1.0, l));
  ParallelRows(height_, config_.render.threads, [&](int y) {
    const float* s = sigma.ptr<float>(y);
    cv::Vec3f* out = buffers->sharp.ptr<cv::Vec3f>(y);
    for (int x = 0; x < width_; ++x) {
      const double level = std::clamp(std::log2(std::max<double>(s[x], sigma_min) / sigma_min), 0.0,
                                      static_cast<double>(levels - 1));
      const int l0 = std::min(static_cast<int>(level), levels - 1);
      const int l1 = std::min(l0 + 1, levels - 1);
      const float w = static_cast<float>(level - l0);
      out[x] += (1 - w) * blurred[l0].at<cv::Vec3f>(y, x) + w * blurred[l1].at<cv::Vec3f>(y, x);
    }
  });
  buffers->blurred.setTo(0);
}

}  // namespace uwscan::sim
