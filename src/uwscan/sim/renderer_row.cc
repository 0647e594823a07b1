// Per-pixel shading of one image row: direct light from floods, ambient and
// lasers (E_d, split into the part that reaches the camera unscattered and
// the part scattered into the small-angle lobe, which becomes E_f), and the
// laser light sheet's single-scattering backscatter (E_b).
#include <algorithm>
#include <cmath>
#include <optional>

#include "uwscan/sim/renderer.h"
#include "uwscan/sim/renderer_internal.h"

namespace uwscan::sim {
namespace {

// Camera-path transmission of light of one wavelength over `range`.
struct PathTransmission {
  double sharp = 1.0;    // Beer–Lambert, eq. 2.1, with the beam attenuation c
  double blurred = 0.0;  // scattered into the forward lobe and still arriving
};

PathTransmission CameraPath(double attenuation, double forward, double range) {
  PathTransmission t;
  t.sharp = std::exp(-attenuation * range);
  if (forward < attenuation) t.blurred = std::max(0.0, std::exp(-forward * range) - t.sharp);
  return t;
}

// Smallest positive l with the ray a + l b (laser frame) on the cone
// y z = p1 x^2 in front of the laser (the plane y = 0 for p1 = 0).
std::optional<double> SheetCrossing(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double p1) {
  if (p1 == 0.0) {
    if (std::abs(b.y()) < 1e-15) return std::nullopt;
    return -a.y() / b.y();
  }
  const double qa = b.y() * b.z() - p1 * b.x() * b.x();
  const double qb = a.y() * b.z() + a.z() * b.y() - 2 * p1 * a.x() * b.x();
  const double qc = a.y() * a.z() - p1 * a.x() * a.x();
  double roots[2];
  int count = 0;
  if (std::abs(qa) < 1e-300) {
    if (std::abs(qb) < 1e-300) return std::nullopt;
    roots[count++] = -qc / qb;
  } else {
    const double disc = qb * qb - 4 * qa * qc;
    if (disc < 0) return std::nullopt;
    const double q = qb >= 0 ? -0.5 * (qb + std::sqrt(disc)) : -0.5 * (qb - std::sqrt(disc));
    roots[count++] = q / qa;
    if (q != 0) roots[count++] = qc / q;
  }
  std::optional<double> best;
  for (int i = 0; i < count; ++i) {
    // The sheet branch: in front of the laser (z > 0); the cone's mirror
    // branch has z < 0 for y z = p1 x^2 with the same sign of y.
    if (roots[i] > 0 && a.z() + roots[i] * b.z() > 0 && (!best || roots[i] < *best))
      best = roots[i];
  }
  return best;
}

}  // namespace

void Renderer::RenderRow(int y, const Rigid3d& world_from_camera,
                         const std::vector<LaserFrame>& lasers, Buffers* buffers) const {
  const Medium& medium = config_.medium;
  const RenderOptions& options = config_.render;
  const Eigen::Matrix3d world_R_camera = world_from_camera.RotationMatrix();
  const Eigen::Vector3d up_in_camera = world_R_camera.transpose() * Eigen::Vector3d::UnitZ();
  std::vector<Eigen::Vector3d> flood_positions_world;
  for (const FloodLight& flood : config_.floods) {
    flood_positions_world.push_back(world_from_camera * flood.camera_from_light.translation);
  }
  const bool ambient = config_.ambient.irradiance_rgb.maxCoeff() > 0;
  const int grid_cols = width_ + 2;
  const float weight = static_cast<float>(buffers->weight);
  cv::Vec3f* sharp_row = buffers->sharp.ptr<cv::Vec3f>(y);
  cv::Vec3f* blurred_row = buffers->blurred.ptr<cv::Vec3f>(y);
  cv::Vec3f* back_row = buffers->back.ptr<cv::Vec3f>(y);
  float* range_row = buffers->range.ptr<float>(y);
  const Eigen::Vector2d sub = buffers->sub_offset;
  const bool supersampled = options.supersample > 1;

  for (int x = 0; x < width_; ++x) {
    const PixelRay& ray = rays_[static_cast<size_t>(y + 1) * grid_cols + x + 1];
    if (ray.direction.squaredNorm() == 0) continue;
    Eigen::Vector3d origin = ray.origin.cast<double>(), direction = ray.direction.cast<double>();
    if (supersampled) RayAt(x + sub.x(), y + sub.y(), &origin, &direction);
    const Eigen::Vector3d origin_world = world_R_camera * origin + world_from_camera.translation;
    const Eigen::Vector3d direction_world = world_R_camera * direction;
    const auto hit =
        config_.scene.Intersect(origin_world, direction_world, 1e-9, options.max_range_m);
    Eigen::Vector3d sharp = Eigen::Vector3d::Zero(), blurred = Eigen::Vector3d::Zero(),
                    back = Eigen::Vector3d::Zero();
    const double ray_length = hit ? hit->lambda : options.max_range_m;

    auto add_light = [&](double radiance, const Optics& optics, double range) {
      const PathTransmission t = CameraPath(optics.attenuation, optics.forward, range);
      const Eigen::Vector3d e = radiance * optics.electrons_per_radiance * optics.response;
      sharp += t.sharp * e;
      blurred += t.blurred * e;
    };

    if (hit) {
      const double range = hit->lambda;
      range_row[x] += static_cast<float>(range * buffers->weight);
      const Eigen::Vector3d point = origin + range * direction;
      Eigen::Vector3d normal = world_R_camera.transpose() * hit->normal_world;
      if (normal.dot(direction) > 0) normal = -normal;  // face the camera
      const double cos_view = -normal.dot(direction);
      const double footprint = range * pixel_angle_rad_ / std::max(cos_view, 0.1);
      const Surface& surface = config_.scene.surfaces[hit->surface];
      const Eigen::Vector3d albedo = surface.texture.Albedo(
          hit->texture_coordinates.x(), hit->texture_coordinates.y(), footprint);

      for (size_t f = 0; f < config_.floods.size(); ++f) {
        const FloodLight& flood = config_.floods[f];
        const Optics& optics = flood_optics_[f];
        const Eigen::Vector3d to_point = point - flood.camera_from_light.translation;
        const double distance = to_point.norm();
        const Eigen::Vector3d unit = to_point / distance;
        const double intensity = flood.Intensity(
            (flood.camera_from_light.rotation * Eigen::Vector3d::UnitZ()).dot(unit));
        const double cos_incidence = -normal.dot(unit);
        if (intensity <= 0 || cos_incidence <= 0) continue;
        if (options.shadows &&
            config_.scene.Occluded(flood_positions_world[f], hit->point_world, hit->surface)) {
          continue;
        }
        const double irradiance = intensity * cos_incidence / (distance * distance) *
                                  std::exp(-optics.forward * distance);
        const double radiance = InterpolateRgb(albedo, flood.wavelength_nm) / M_PI * irradiance;
        add_light(radiance, optics, range);
      }

      if (ambient) {
        // Uniform sky over the upper hemisphere: E (1 + cos tilt) / 2.
        const double cos_sky = 0.5 * (1.0 + normal.dot(up_in_camera));
        for (int k = 0; k < 3; ++k) {
          const double radiance = albedo[k] / M_PI * config_.ambient.irradiance_rgb[k] * cos_sky;
          add_light(radiance, channel_optics_[k], range);
        }
      }

      for (const LaserFrame& laser : lasers) {
        // Cheap test on the centre ray, then n x n sub-rays across the pixel
        // footprint so the rendered line's sub-pixel peak is unbiased.
        const Eigen::Vector3d p =
            laser.laser_R_camera * (point - laser.camera_from_laser.translation);
        if (!(p.z() > 0)) continue;
        const LaserSource& source = config_.lasers[laser.source];
        const double xl = p.x() / p.z();
        const double offset = std::abs((p.y() / p.z() - laser.p1 * xl * xl) * p.z());
        const double laser_range = p.norm();
        const double sigma = 0.25 * (source.width_m + source.divergence_rad * laser_range);
        if (options.forward_scatter) {
          // The wide halo is smooth: one sample at the pixel centre.
          const double spread = medium.forward_angle_rad * laser_range;
          const double b = laser.optics.scattering;
          const double halo_sigma =
              std::sqrt(sigma * sigma + spread * spread * (1 + b * laser_range) / 3);
          if (offset < 6 * halo_sigma) {
            const double radiance =
                LaserRadiance(laser, world_from_camera, point, normal, albedo, SheetPart::kHalo);
            if (radiance > 0) add_light(radiance, laser.optics, range);
          }
        }
        if (offset > 6 * sigma + 2 * footprint) continue;
        // With global supersampling each pass is one sub-ray already.
        const int n = supersampled ? 1 : options.laser_supersample;
        for (int j = 0; j < n; ++j) {
          for (int i = 0; i < n; ++i) {
            Eigen::Vector3d sub_origin = origin, sub_direction = direction;
            if (n > 1) {
              RayAt(x + (i + 0.5) / n - 0.5, y + (j + 0.5) / n - 0.5, &sub_origin, &sub_direction);
            }
            const auto sub_hit =
                config_.scene.Intersect(world_R_camera * sub_origin + world_from_camera.translation,
                                        world_R_camera * sub_direction, 1e-9, options.max_range_m);
            if (!sub_hit) continue;
            const Eigen::Vector3d sub_point = sub_origin + sub_hit->lambda * sub_direction;
            Eigen::Vector3d sub_normal = world_R_camera.transpose() * sub_hit->normal_world;
            if (sub_normal.dot(sub_direction) > 0) sub_normal = -sub_normal;
            const Eigen::Vector3d sub_albedo =
                config_.scene.surfaces[sub_hit->surface].texture.Albedo(
                    sub_hit->texture_coordinates.x(), sub_hit->texture_coordinates.y(),
                    footprint / n);
            const double radiance = LaserRadiance(laser, world_from_camera, sub_point, sub_normal,
                                                  sub_albedo, SheetPart::kCore);
            if (radiance > 0) add_light(radiance / (n * n), laser.optics, sub_hit->lambda);
          }
        }
      }
    }

    if (options.backscatter) {
      // Laser sheet backscatter: the camera ray crosses the sheet once; the
      // Gaussian cross-section integrates along the ray to 1/|n·d|.
      for (const LaserFrame& laser : lasers) {
        const LaserSource& source = config_.lasers[laser.source];
        const Optics& optics = laser.optics;
        const double b = optics.scattering;
        if (b <= 0 || source.power_w <= 0) continue;
        // Ray in the laser frame: a + l b; crossing of the cone
        // (a_y + l b_y)(a_z + l b_z) = p1 (a_x + l b_x)^2, eq. 4.30.
        const Eigen::Vector3d a =
            laser.laser_R_camera * (origin - laser.camera_from_laser.translation);
        const Eigen::Vector3d bl = laser.laser_R_camera * direction;
        const auto l = SheetCrossing(a, bl, laser.p1);
        if (!l || !(*l > 0 && *l < ray_length)) continue;
        const double s = *l;
        const Eigen::Vector3d p = a + s * bl;
        if (!(p.z() > 0) || std::abs(p.x() / p.z()) > laser.tan_half_fan) continue;
        const double laser_range = p.norm();
        const Eigen::Vector3d gradient(
            -2 * laser.p1 * p.x() / (p.z() * p.z()), 1 / p.z(),
            -p.y() / (p.z() * p.z()) + 2 * laser.p1 * p.x() * p.x() / (p.z() * p.z() * p.z()));
        const double crossing_cos = std::abs(gradient.normalized().dot(bl));
        const double path_factor = 1.0 / std::max(crossing_cos, 0.05);
        const double phase = medium.Phase(-p.dot(bl) / laser_range);
        const double k = optics.forward;
        const double radiance = b * phase * source.power_w / (source.fan_angle_rad * laser_range) *
                                path_factor * std::exp(-k * (laser_range + s));
        back += radiance * optics.electrons_per_radiance * optics.response;
      }
      // Veiling light of the ambient daylight (isotropic single scattering).
      if (ambient) {
        for (int k = 0; k < 3; ++k) {
          const Optics& optics = channel_optics_[k];
          if (optics.attenuation <= 0) continue;
          const double veil = optics.scattering / optics.attenuation *
                              config_.ambient.irradiance_rgb[k] / (2 * M_PI);
          back[k] += veil * (1 - std::exp(-optics.attenuation * ray_length)) *
                     optics.electrons_per_radiance;
        }
      }
    }

    for (int k = 0; k < 3; ++k) {
      sharp_row[x][k] += weight * static_cast<float>(sharp[k]);
      blurred_row[x][k] += weight * static_cast<float>(blurred[k]);
      back_row[x][k] += weight * static_cast<float>(back[k]);
    }
  }
}

}  // namespace uwscan::sim
