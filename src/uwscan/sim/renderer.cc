#include "uwscan/sim/renderer.h"

#include <algorithm>
#include <cmath>

#include "uwscan/sensor/line_projector.h"
#include "uwscan/sim/renderer_internal.h"
#include "uwscan/util/error.h"

namespace uwscan::sim {
namespace {

// Unpolarised Fresnel reflectance at an interface (n1 -> n2), eq. 2.4
// generalised to oblique incidence.
double FresnelReflectance(double n1, double cos1, double n2, double cos2) {
  const double rs = (n1 * cos1 - n2 * cos2) / (n1 * cos1 + n2 * cos2);
  const double rp = (n1 * cos2 - n2 * cos1) / (n1 * cos2 + n2 * cos1);
  return 0.5 * (rs * rs + rp * rp);
}

// Radiance transfer from water into the camera through the port: Fresnel
// transmission of both interfaces, the n^2 law of radiance, and cos^4
// off-axis fall-off of the lens.
double PixelGain(const Camera& camera, const Eigen::Vector2d& pixel, const Eigen::Vector3d& ray) {
  const auto& k = camera.intrinsics;
  const Eigen::Vector3d pinhole((pixel.x() - k[2]) / k[0], (pixel.y() - k[3]) / k[1], 1.0);
  const double cos_axis = 1.0 / pinhole.norm();
  const double vignetting = std::pow(cos_axis, 4);
  if (!camera.IsFlatPort()) return vignetting;
  const FlatPort& port = camera.port;
  const double cos_w = std::clamp(std::abs(ray.dot(port.normal)), 0.0, 1.0);
  const double sin_w = std::sqrt(1 - cos_w * cos_w);
  const double sin_g = port.n_water / port.n_glass * sin_w;
  const double sin_a = port.n_water / port.n_air * sin_w;
  if (sin_g >= 1 || sin_a >= 1) return 0.0;
  const double cos_g = std::sqrt(1 - sin_g * sin_g), cos_a = std::sqrt(1 - sin_a * sin_a);
  const double transmission = (1 - FresnelReflectance(port.n_water, cos_w, port.n_glass, cos_g)) *
                              (1 - FresnelReflectance(port.n_glass, cos_g, port.n_air, cos_a));
  const double radiance_law = std::pow(port.n_air / port.n_water, 2);
  return transmission * radiance_law * vignetting;
}

}  // namespace

void RenderOptions::Check(const std::string& context) const {
  UWS_CHECK(supersample >= 1 && supersample <= 8, context, ": supersample must be 1..8");
  UWS_CHECK(laser_supersample >= 1 && laser_supersample <= 16, context,
            ": laser_supersample must be 1..16");
  UWS_CHECK(backscatter_step_px >= 0 && backscatter_step_px <= 64, context,
            ": backscatter_step_px must be 0 (auto) .. 64");
  UWS_CHECK(backscatter_samples >= 1 && backscatter_samples <= 256, context,
            ": backscatter_samples must be 1..256");
  UWS_CHECK(std::isfinite(max_range_m) && max_range_m > 0, context, ": max_range_m must be > 0");
  UWS_CHECK(threads >= 1 && threads <= 256, context, ": threads must be 1..256");
}

void SimConfig::Check() const {
  rig.Check("rig");
  scene.Check("scene");
  medium.Check("medium");
  for (size_t i = 0; i < lasers.size(); ++i) {
    const std::string context = "lasers[" + std::to_string(i) + "]";
    lasers[i].Check(context);
    UWS_CHECK(static_cast<size_t>(lasers[i].rig_laser) < rig.lasers.size(), context,
              ": refers to rig laser ", lasers[i].rig_laser, " but the rig has ",
              rig.lasers.size());
  }
  for (size_t i = 0; i < floods.size(); ++i) floods[i].Check("floods[" + std::to_string(i) + "]");
  ambient.Check("ambient");
  snow.Check("snow");
  sensor.Check("sensor");
  render.Check("render");
  if (sensor.output == OutputFormat::kBayer) {
    UWS_CHECK(rig.cameras.front().bayer != "none",
              "sensor: Bayer output needs a camera with a "
              "bayer pattern in the rig");
  }
}

Renderer::Renderer(SimConfig config) : config_(std::move(config)) {
  config_.Check();
  config_.scene.Prepare();
  const Camera& cam = camera();
  width_ = cam.width;
  height_ = cam.height;
  const int grid_cols = width_ + 2;
  rays_.assign(static_cast<size_t>(grid_cols) * (height_ + 2),
               PixelRay{Eigen::Vector3f::Zero(), Eigen::Vector3f::Zero()});
  pixel_gain_.assign(static_cast<size_t>(width_) * height_, 0.0f);
  ParallelRows(height_ + 2, config_.render.threads, [&](int gy) {
    for (int gx = 0; gx < grid_cols; ++gx) {
      const Eigen::Vector2d pixel(gx - 1, gy - 1);
      const auto ray = cam.BackProject(pixel);
      if (!ray) continue;
      rays_[static_cast<size_t>(gy) * grid_cols + gx] = {ray->origin.cast<float>(),
                                                         ray->direction.cast<float>()};
      if (gx >= 1 && gy >= 1 && gx <= width_ && gy <= height_) {
        pixel_gain_[static_cast<size_t>(gy - 1) * width_ + gx - 1] =
            static_cast<float>(PixelGain(cam, pixel, ray->direction));
      }
    }
  });
  for (const FloodLight& flood : config_.floods)
    flood_optics_.push_back(MakeOptics(flood.wavelength_nm));
  for (const LaserSource& laser : config_.lasers) {
    laser_optics_.push_back(MakeOptics(config_.rig.lasers[laser.rig_laser].wavelength_nm));
  }
  for (int k = 0; k < 3; ++k) {
    channel_optics_[k] = MakeOptics(kChannelWavelengthNm[k]);
    channel_optics_[k].response = Eigen::Vector3d::Unit(k);
  }
  const double n_water = cam.IsFlatPort() ? cam.port.n_water : 1.0;
  pixel_angle_rad_ = 1.0 / (cam.intrinsics[0] * n_water);

  const int step = BackscatterStep();
  coarse_cols_ = (width_ - 1 + step - 1) / step + 1;
  coarse_rows_ = (height_ - 1 + step - 1) / step + 1;
  coarse_rays_.assign(static_cast<size_t>(coarse_cols_) * coarse_rows_,
                      PixelRay{Eigen::Vector3f::Zero(), Eigen::Vector3f::Zero()});
  for (int j = 0; j < coarse_rows_; ++j) {
    for (int i = 0; i < coarse_cols_; ++i) {
      const auto ray = cam.BackProject(Eigen::Vector2d(i * step, j * step));
      if (ray) {
        coarse_rays_[static_cast<size_t>(j) * coarse_cols_ + i] = {ray->origin.cast<float>(),
                                                                   ray->direction.cast<float>()};
      }
    }
  }
}

int Renderer::BackscatterStep() const {
  if (config_.render.backscatter_step_px > 0) return config_.render.backscatter_step_px;
  return std::max(1, width_ / 80);
}

Renderer::Optics Renderer::MakeOptics(double wavelength_nm) const {
  const Medium& medium = config_.medium;
  Optics optics;
  optics.wavelength_nm = wavelength_nm;
  optics.attenuation = medium.Attenuation(wavelength_nm);
  optics.forward = config_.render.forward_scatter
                       ? medium.ForwardTransmissionCoefficient(wavelength_nm)
                       : optics.attenuation;
  optics.scattering = medium.Scattering(wavelength_nm);
  optics.response = ChannelResponse(wavelength_nm);
  optics.electrons_per_radiance = config_.sensor.ElectronsPerRadiance(wavelength_nm);
  return optics;
}

Rigid3d Renderer::CameraFromLaser(size_t source, double angle_rad) const {
  UWS_CHECK(source < config_.lasers.size(), "laser source ", source, " out of range");
  const LaserSource& laser = config_.lasers[source];
  const Rigid3d at_zero = config_.rig.CameraFromLaser(0, laser.rig_laser);
  return laser.servo ? at_zero * laser.ServoRotation(angle_rad) : at_zero;
}

std::vector<Renderer::LaserFrame> Renderer::MakeLaserFrames(const FrameState& state) const {
  UWS_CHECK(
      state.laser_angles_rad.empty() || state.laser_angles_rad.size() == config_.lasers.size(),
      "FrameState: laser_angles_rad must be empty or have one angle per laser (got ",
      state.laser_angles_rad.size(), " for ", config_.lasers.size(), ")");
  std::vector<LaserFrame> frames;
  if (!state.lasers_on) return frames;
  for (size_t i = 0; i < config_.lasers.size(); ++i) {
    const LaserSource& source = config_.lasers[i];
    const LineProjector& projector = config_.rig.lasers[source.rig_laser];
    LaserFrame frame;
    frame.source = static_cast<int>(i);
    frame.camera_from_laser =
        CameraFromLaser(i, state.laser_angles_rad.empty() ? 0.0 : state.laser_angles_rad[i]);
    frame.laser_from_camera = frame.camera_from_laser.Inverse();
    frame.laser_R_camera = frame.laser_from_camera.RotationMatrix();
    const Eigen::Quaterniond& q = frame.camera_from_laser.rotation;
    frame.q_wxyz = {q.w(), q.x(), q.y(), q.z()};
    frame.p1 = projector.p1;
    frame.tan_half_fan = std::tan(0.5 * source.fan_angle_rad);
    frame.optics = laser_optics_[i];
    frames.push_back(frame);
  }
  return frames;
}

void Renderer::RayAt(double u, double v, Eigen::Vector3d* origin,
                     Eigen::Vector3d* direction) const {
  const int grid_cols = width_ + 2;
  const double gx = std::clamp(u + 1.0, 0.0, static_cast<double>(width_ + 1) - 1e-9);
  const double gy = std::clamp(v + 1.0, 0.0, static_cast<double>(height_ + 1) - 1e-9);
  const int x0 = std::min(static_cast<int>(gx), width_),
            y0 = std::min(static_cast<int>(gy), height_);
  const double fx = gx - x0, fy = gy - y0;
  const PixelRay* r = &rays_[static_cast<size_t>(y0) * grid_cols + x0];
  const double w[4] = {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy};
  const PixelRay* corners[4] = {r, r + 1, r + grid_cols, r + grid_cols + 1};
  origin->setZero();
  direction->setZero();
  for (int i = 0; i < 4; ++i) {
    *origin += w[i] * corners[i]->origin.cast<double>();
    *direction += w[i] * corners[i]->direction.cast<double>();
  }
  direction->normalize();
}

double Renderer::LaserRadiance(const LaserFrame& laser, const Rigid3d& world_from_camera,
                               const Eigen::Vector3d& point,
                               const Eigen::Vector3d& normal_to_camera,
                               const Eigen::Vector3d& albedo, SheetPart part) const {
  const LaserSource& source = config_.lasers[laser.source];
  const Eigen::Vector3d p = laser.laser_R_camera * (point - laser.camera_from_laser.translation);
  if (!(p.z() > 0)) return 0.0;
  const double x = p.x() / p.z();
  if (std::abs(x) > laser.tan_half_fan) return 0.0;
  // Offset from the bent sheet: residual of eq. 4.30 (tangent of the angle
  // off the sheet) times depth; exact perpendicular distance for p1 = 0.
  const double offset = (p.y() / p.z() - laser.p1 * x * x) * p.z();
  const double range = p.norm();
  const double sigma = 0.25 * (source.width_m + source.divergence_rad * range);
  const Optics& optics = laser.optics;
  const double sharp = std::exp(-optics.attenuation * range);
  double profile = 0.0;
  if (part == SheetPart::kCore) {
    profile = sharp * Gaussian(offset, sigma);
  } else if (config_.render.forward_scatter) {
    // Forward scattering on the way out widens the sheet (second Gaussian).
    const double total = std::exp(-optics.forward * range);
    const double spread = config_.medium.forward_angle_rad * range;
    const double sigma_scattered =
        std::sqrt(sigma * sigma + spread * spread * (1 + optics.scattering * range) / 3);
    profile += std::max(0.0, total - sharp) * Gaussian(offset, sigma_scattered);
  }
  if (profile < 1e-12) return 0.0;
  const Eigen::Vector3d beam = laser.camera_from_laser.rotation * (p / range);
  const double cos_incidence = -beam.dot(normal_to_camera);
  if (cos_incidence <= 0) return 0.0;  // lit from the other side
  // Shadows of the core only: the halo is scattered light, not a ray.
  if (part == SheetPart::kCore && config_.render.shadows &&
      config_.scene.Occluded(world_from_camera * laser.camera_from_laser.translation,
                             world_from_camera * point)) {
    return 0.0;
  }
  const double power_per_length = source.power_w / (source.fan_angle_rad * range);
  const double irradiance = power_per_length * profile * cos_incidence;
  return InterpolateRgb(albedo, optics.wavelength_nm) / M_PI * irradiance;
}

RenderedFrame Renderer::Render(const FrameState& state) const {
  const std::vector<LaserFrame> lasers = MakeLaserFrames(state);
  Buffers buffers;
  buffers.sharp = cv::Mat::zeros(height_, width_, CV_32FC3);
  buffers.blurred = cv::Mat::zeros(height_, width_, CV_32FC3);
  buffers.back = cv::Mat::zeros(height_, width_, CV_32FC3);
  buffers.range = cv::Mat::zeros(height_, width_, CV_32F);
  std::vector<Rigid3d> poses = state.exposure_poses;
  if (poses.empty()) poses.push_back(state.world_from_camera);
  buffers.weight = 1.0 / poses.size();
  for (const Rigid3d& pose : poses) RenderPose(pose, lasers, &buffers);
  if (config_.render.forward_scatter) AddForwardScatter(&buffers);

  RenderedFrame frame;
  frame.electrons.create(height_, width_, CV_32FC3);
  ParallelRows(height_, config_.render.threads, [&](int y) {
    cv::Vec3f* out = frame.electrons.ptr<cv::Vec3f>(y);
    const cv::Vec3f* sharp = buffers.sharp.ptr<cv::Vec3f>(y);
    const cv::Vec3f* blurred = buffers.blurred.ptr<cv::Vec3f>(y);
    const cv::Vec3f* back = buffers.back.ptr<cv::Vec3f>(y);
    const float* gain = &pixel_gain_[static_cast<size_t>(y) * width_];
    for (int x = 0; x < width_; ++x) out[x] = (sharp[x] + blurred[x] + back[x]) * gain[x];
  });
  if (config_.snow.per_m3 > 0) {
    for (const Rigid3d& pose : poses) {
      AddMarineSnow(pose, lasers, buffers.range, buffers.weight, &frame.electrons);
    }
  }
  frame.range_m = buffers.range;
  frame.image = Digitize(frame.electrons, config_.sensor, camera().bayer, state.noise_seed,
                         config_.render.threads);
  return frame;
}

void Renderer::RenderPose(const Rigid3d& world_from_camera, const std::vector<LaserFrame>& lasers,
                          Buffers* buffers) const {
  const int n = config_.render.supersample;
  const double pose_weight = buffers->weight;
  buffers->weight = pose_weight / (n * n);
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      buffers->sub_offset = n == 1 ? Eigen::Vector2d::Zero()
                                   : Eigen::Vector2d((i + 0.5) / n - 0.5, (j + 0.5) / n - 0.5);
      ParallelRows(height_, config_.render.threads,
                   [&](int y) { RenderRow(y, world_from_camera, lasers, buffers); });
    }
  }
  buffers->weight = pose_weight;
  buffers->sub_offset.setZero();
  if (config_.render.backscatter && !config_.floods.empty()) {
    AddFloodBackscatter(world_from_camera, buffers);
  }
}

}  // namespace uwscan::sim
