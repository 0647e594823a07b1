// Marine snow (issue 3, optional): particles fixed in the world, hashed per
// 0.5 m cell from the seed, so they stay put between frames and the same
// seed gives the same snow. Each particle is a diffuse sphere of radius r
// and albedo 0.8, radiant intensity J = albedo E r^2 towards the camera
// (E: irradiance from the floods and the laser core), seen through the
// water (exp(-c d)) and the port as a point source of J A / d^2 on the lens
// aperture A, spread over a Gaussian blob of the defocus circle.
#include <cmath>

#include "uwscan/sim/random.h"
#include "uwscan/sim/renderer.h"
#include "uwscan/sim/renderer_internal.h"
#include "uwscan/util/error.h"

namespace uwscan::sim {

void MarineSnow::Check(const std::string& context) const {
  UWS_CHECK(std::isfinite(per_m3) && per_m3 >= 0 && per_m3 <= 10000, context,
            ": particles per m^3 must be in [0, 10000]");
  UWS_CHECK(std::isfinite(max_range_m) && max_range_m > 0, context, ": max_range_m must be > 0");
  UWS_CHECK(std::isfinite(focus_m) && focus_m > 0, context, ": focus_m must be > 0");
}

void Renderer::AddMarineSnow(const Rigid3d& world_from_camera,
                             const std::vector<LaserFrame>& lasers, const cv::Mat& range_m,
                             double weight, cv::Mat* electrons) const {
  const MarineSnow& snow = config_.snow;
  const Camera& cam = camera();
  const SensorOptions& sensor = config_.sensor;
  constexpr double kCell = 0.5, kAlbedo = 0.8;
  const Rigid3d camera_from_world = world_from_camera.Inverse();
  const Eigen::Vector3d centre = world_from_camera.translation;
  const int reach = static_cast<int>(std::ceil(snow.max_range_m / kCell));
  const Eigen::Vector3i base = (centre / kCell).array().floor().cast<int>();
  const double mean_per_cell = snow.per_m3 * kCell * kCell * kCell;
  const double focal_m = cam.intrinsics[0] * sensor.pixel_pitch_m;
  const double aperture_m = focal_m / sensor.f_number;
  const double aperture_area = M_PI * 0.25 * aperture_m * aperture_m;
  const double n_water = cam.IsFlatPort() ? cam.port.n_water : 1.0;

  for (int i = -reach; i <= reach; ++i) {
    for (int j = -reach; j <= reach; ++j) {
      for (int k = -reach; k <= reach; ++k) {
        const Eigen::Vector3i cell = base + Eigen::Vector3i(i, j, k);
        Rng rng(StreamSeed(snow.seed,
                           static_cast<uint64_t>(cell.x()) * 73856093ULL ^
                               static_cast<uint64_t>(cell.y()) * 19349663ULL,
                           static_cast<uint64_t>(cell.z())));
        // Poisson count by inversion (small means).
        int count = 0;
        for (double p = std::exp(-mean_per_cell), u = rng.Uniform(), sum = p;
             u > sum && count < 1000;) {
          ++count;
          p *= mean_per_cell / count;
          sum += p;
        }
        for (int n = 0; n < count; ++n) {
          const Eigen::Vector3d world =
              (cell.cast<double>() + Eigen::Vector3d(rng.Uniform(), rng.Uniform(), rng.Uniform())) *
              kCell;
          const double radius = 0.0003 * std::pow(5.0, rng.Uniform());
          const Eigen::Vector3d point = camera_from_world * world;
          const double distance = point.norm();
          if (point.z() < 0.05 || distance > snow.max_range_m) continue;
          const auto pixel = cam.Project(point, ProjectionMethod::kExact);
          if (!pixel || !cam.InImage(*pixel)) continue;
          const int px = static_cast<int>(std::lround(pixel->x())),
                    py = static_cast<int>(std::lround(pixel->y()));
          const float surface = range_m.at<float>(py, px);
          if (surface > 0 && distance > surface) continue;  // behind the scene
          // Irradiance from the lights.
          Eigen::Vector3d signal = Eigen::Vector3d::Zero();
          auto add = [&](double irradiance, const Optics& optics) {
            const double intensity = kAlbedo * irradiance * radius * radius;  // W/sr
            const double power = intensity * aperture_area / (distance * distance) *
                                 std::exp(-optics.attenuation * distance);
            const double photons =
                power * sensor.exposure_s * optics.wavelength_nm * 1e-9 / 1.98644586e-25;
            signal += photons * sensor.quantum_efficiency * optics.response;
          };
          for (size_t f = 0; f < config_.floods.size(); ++f) {
            const FloodLight& flood = config_.floods[f];
            const Eigen::Vector3d to = point - flood.camera_from_light.translation;
            const double r = to.norm();
            const double cos_axis =
                (flood.camera_from_light.rotation * Eigen::Vector3d::UnitZ()).dot(to / r);
            add(flood.Intensity(cos_axis) / (r * r) * std::exp(-flood_optics_[f].forward * r),
                flood_optics_[f]);
          }
          for (const LaserFrame& laser : lasers) {
            const LaserSource& source = config_.lasers[laser.source];
            const Eigen::Vector3d p =
                laser.laser_R_camera * (point - laser.camera_from_laser.translation);
            if (!(p.z() > 0) || std::abs(p.x() / p.z()) > laser.tan_half_fan) continue;
            const double x = p.x() / p.z(), range = p.norm();
            const double offset = (p.y() / p.z() - laser.p1 * x * x) * p.z();
            const double sigma = 0.25 * (source.width_m + source.divergence_rad * range);
            add(source.power_w / (source.fan_angle_rad * range) * Gaussian(offset, sigma) *
                    std::exp(-laser.optics.attenuation * range),
                laser.optics);
          }
          // Fresnel transmission and cos^4 (not the radiance n^2 law: a point source).
          const double gain =
              pixel_gain_[static_cast<size_t>(py) * width_ + px] * n_water * n_water;
          signal *= gain * weight;
          // Defocus: blur circle f D |1/d - 1/d_focus| (apparent distances d/n).
          const double blur_px = cam.intrinsics[0] * aperture_m *
                                 std::abs(n_water / distance - n_water / snow.focus_m);
          const double sigma_px = std::max(0.5, blur_px / 3.0);
          const int half = static_cast<int>(std::ceil(3 * sigma_px));
          double norm = 0;
          for (int dy = -half; dy <= half; ++dy) {
            for (int dx = -half; dx <= half; ++dx) {
              norm += std::exp(-0.5 * (dx * dx + dy * dy) / (sigma_px * sigma_px));
            }
          }
          for (int dy = -half; dy <= half; ++dy) {
            for (int dx = -half; dx <= half; ++dx) {
              const int x = px + dx, y = py + dy;
              if (x < 0 || y < 0 || x >= width_ || y >= height_) continue;
              const double w = std::exp(-0.5 * (dx * dx + dy * dy) / (sigma_px * sigma_px)) / norm;
              cv::Vec3f& out = electrons->at<cv::Vec3f>(y, x);
              for (int c = 0; c < 3; ++c) out[c] += static_cast<float>(w * signal[c]);
            }
          }
        }
      }
    }
  }
}

}  // namespace uwscan::sim
