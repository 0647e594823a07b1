// In-memory underwater image formation (thesis eq. 2.6, E_T = E_d + E_f + E_b):
// refractive ray tracing through the rig's flat port (per-pixel rays
// precomputed once), analytic scene, line lasers and flood lights with
// Beer–Lambert attenuation, single-scattering backscatter, range-dependent
// forward-scatter blur, and the sensor model. Usable from tests of every
// layer without touching the disk:
//
//   sim::Renderer renderer(config);
//   sim::FrameState state{.world_from_camera = pose, .laser_angles_rad = {0.1}};
//   sim::RenderedFrame frame = renderer.Render(state);        // frame.image
//   auto truth = renderer.LaserGroundTruth(state);            // u, v, x, y, z
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "uwscan/sensor/rig.h"
#include "uwscan/sim/lights.h"
#include "uwscan/sim/medium.h"
#include "uwscan/sim/scene.h"
#include "uwscan/sim/sensor_model.h"

namespace uwscan::sim {

struct RenderOptions {
  int supersample = 1;           // n x n camera rays per pixel (textures are box-filtered anyway)
  int laser_supersample = 4;     // n x n sub-rays in pixels near a laser line
  int backscatter_step_px = 0;   // grid step of the flood-light backscatter (0: width / 80)
  int backscatter_samples = 12;  // samples along each camera ray
  double max_range_m = 30.0;     // open water beyond
  bool forward_scatter = true;   // E_f: blur growing with range and turbidity
  bool backscatter = true;       // E_b
  bool shadows = true;
  int threads = 2;

  void Check(const std::string& context) const;
};

// Marine snow: world-fixed particles (0.3–1.5 mm, albedo 0.8) lit by the
// floods and lasers, drawn as defocused blobs in front of the scene.
struct MarineSnow {
  double per_m3 = 0.0;       // particle density
  double max_range_m = 3.0;  // drawn up to this distance from the camera
  double focus_m = 2.0;      // focus distance (in water) for the defocus blur
  uint64_t seed = 1;
  void Check(const std::string& context) const;
};

// Everything that defines the images (camera 0 of the rig renders).
struct SimConfig {
  Rig rig;
  Scene scene;
  Medium medium;
  std::vector<LaserSource> lasers;
  std::vector<FloodLight> floods;
  Ambient ambient;
  SensorOptions sensor;
  RenderOptions render;
  MarineSnow snow;

  void Check() const;
};

struct FrameState {
  Rigid3d world_from_camera;
  std::vector<double> laser_angles_rad;  // servo angle per laser source (empty = 0)
  bool lasers_on = true;                 // false: the lasers are off in this frame
  // Poses spread over the exposure for motion blur; empty = world_from_camera.
  std::vector<Rigid3d> exposure_poses;
  uint64_t noise_seed = 1;
};

struct RenderedFrame {
  cv::Mat image;      // as stored: CV_8U/CV_16U, 1 channel (Bayer, mono) or 3 (B G R)
  cv::Mat electrons;  // CV_32FC3 (R G B) before noise and quantisation
  cv::Mat range_m;    // CV_32F: length of each pixel's ray in water to the scene (0 = none)
};

struct LaserPoint {
  int laser = 0;                    // index of the laser source
  Eigen::Vector2d pixel;            // exact projection of point_in_camera
  Eigen::Vector3d point_in_camera;  // on the scene and on the light sheet
};

class Renderer {
 public:
  // Checks the configuration and precomputes the per-pixel refracted rays.
  explicit Renderer(SimConfig config);

  RenderedFrame Render(const FrameState& state) const;

  // True laser-line points visible in the image: canonical x sampled along
  // the line so that neighbours are about `spacing_px` apart.
  std::vector<LaserPoint> LaserGroundTruth(const FrameState& state, double spacing_px = 1.0) const;

  // camera_from_laser of a laser source at a servo angle.
  Rigid3d CameraFromLaser(size_t source, double angle_rad) const;

  const SimConfig& config() const { return config_; }
  const Camera& camera() const { return config_.rig.cameras.front(); }

 private:
  struct PixelRay {
    Eigen::Vector3f origin, direction;
  };
  struct LaserFrame;  // per-frame laser pose data
  struct Buffers;
  // Medium and sensor constants of light of one wavelength.
  struct Optics {
    double wavelength_nm = 0.0;
    double attenuation = 0.0;  // c, 1/m
    double forward = 0.0;      // attenuation of sharp + forward-lobe light (c without it if off)
    double scattering = 0.0;   // b, 1/m
    Eigen::Vector3d response = Eigen::Vector3d::Zero();  // sensor channels
    double electrons_per_radiance = 0.0;
  };
  Optics MakeOptics(double wavelength_nm) const;

  // Ray through a (possibly sub-pixel) position, interpolated from the grid.
  void RayAt(double u, double v, Eigen::Vector3d* origin, Eigen::Vector3d* direction) const;
  void RenderPose(const Rigid3d& world_from_camera, const std::vector<LaserFrame>& lasers,
                  Buffers* buffers) const;
  void RenderRow(int y, const Rigid3d& world_from_camera, const std::vector<LaserFrame>& lasers,
                 Buffers* buffers) const;
  // Laser radiance (W m^-2 sr^-1) leaving a camera-frame surface point: the
  // sheet's unscattered core and/or its forward-scattered halo.
  enum class SheetPart { kCore, kHalo };
  double LaserRadiance(const LaserFrame& laser, const Rigid3d& world_from_camera,
                       const Eigen::Vector3d& point, const Eigen::Vector3d& normal_to_camera,
                       const Eigen::Vector3d& albedo, SheetPart part) const;
  void AddFloodBackscatter(const Rigid3d& world_from_camera, Buffers* buffers) const;
  void AddForwardScatter(Buffers* buffers) const;
  // Adds marine snow seen from one pose to `electrons` (after the pixel gain).
  void AddMarineSnow(const Rigid3d& world_from_camera, const std::vector<LaserFrame>& lasers,
                     const cv::Mat& range_m, double weight, cv::Mat* electrons) const;
  std::vector<LaserFrame> MakeLaserFrames(const FrameState& state) const;
  int BackscatterStep() const;

  SimConfig config_;
  int width_ = 0, height_ = 0;
  std::vector<PixelRay> rays_;     // (width + 2) x (height + 2), pixel centres -1 .. width
  std::vector<float> pixel_gain_;  // Fresnel transmission x cos^4 x (n_air / n_water)^2
  double pixel_angle_rad_ = 0.0;   // angular size of a pixel in water
  int coarse_cols_ = 0, coarse_rows_ = 0;
  std::vector<PixelRay> coarse_rays_;
  std::vector<Optics> flood_optics_, laser_optics_;
  Optics channel_optics_[3];  // broadband light in the R, G, B bands (response = unit vector)
};

}  // namespace uwscan::sim
