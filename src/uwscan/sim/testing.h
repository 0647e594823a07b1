// Small scenes for tests of any layer (header only, no disk access): the
// thesis scanner above a uniform plane, a camera pose looking down, and the
// ground-truth laser crossing of an image row.
//
//   SimConfig config = sim::testing::PlaneConfig(320, 240, "clear");
//   sim::Renderer renderer(config);
//   sim::FrameState state{.world_from_camera = sim::testing::LookingDown(2.0),
//                         .laser_angles_rad = {-0.1}};
//   cv::Mat image = renderer.Render(state).image;
#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "uwscan/sim/renderer.h"
#include "uwscan/sim/scenario.h"

namespace uwscan::sim::testing {

// Camera looking straight down (world z up), `altitude` m above the origin.
inline Rigid3d LookingDown(double altitude) {
  Eigen::Matrix3d axes;
  axes << 1, 0, 0, 0, -1, 0, 0, 0, -1;
  return Rigid3d(Eigen::Quaterniond(axes), Eigen::Vector3d(0, 0, altitude));
}

// Thesis scanner (tank-target rig) above a uniform grey plane through the
// world origin, tilted by `tilt` about x so the range varies along the line.
inline SimConfig PlaneConfig(int width, int height, const std::string& water, double tilt = 0.15) {
  ScenarioOptions options;
  options.width = width;
  options.height = height;
  options.turbidity = water;
  options.output = OutputFormat::kRgb;
  SimConfig config = MakeScenario("tank-target", options).config;
  Surface plane;
  plane.name = "target";
  plane.size_x = plane.size_y = 20.0;
  plane.texture.type = TextureType::kUniform;
  plane.texture.albedo = {0.5, 0.5, 0.5};
  plane.world_from_surface =
      Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(tilt, Eigen::Vector3d::UnitX())),
              Eigen::Vector3d::Zero());
  config.scene.surfaces = {plane};
  config.floods.clear();
  config.sensor.noise = false;
  return config;
}

// Interpolates the ground-truth u at image row v from points ~1 px apart.
inline std::optional<double> TruthAtRow(const std::vector<LaserPoint>& truth, double row) {
  for (size_t i = 1; i < truth.size(); ++i) {
    const Eigen::Vector2d& a = truth[i - 1].pixel;
    const Eigen::Vector2d& b = truth[i].pixel;
    if ((a.y() - row) * (b.y() - row) <= 0 && std::abs(b.y() - a.y()) > 1e-9 &&
        (b - a).norm() < 3.0) {
      const double w = (row - a.y()) / (b.y() - a.y());
      return a.x() + w * (b.x() - a.x());
    }
  }
  return std::nullopt;
}

// A scenario at 320x240 (its own motion, rig and scene, `frames` long),
// its scene prepared for rendering and ray casts.
inline Scenario SmallScenario(const std::string& name, int frames) {
  ScenarioOptions options;
  options.width = 320;
  options.height = 240;
  options.frames = frames;
  Scenario scenario = MakeScenario(name, options);
  scenario.config.scene.Prepare();
  return scenario;
}

}  // namespace uwscan::sim::testing
