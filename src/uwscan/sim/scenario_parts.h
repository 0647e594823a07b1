// Building blocks shared by the scenario definitions (internal to sim/).
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <string>

#include "uwscan/sim/random.h"
#include "uwscan/sim/scenario.h"

namespace uwscan::sim::internal {

inline constexpr double kDeg = M_PI / 180.0;

inline Eigen::Quaterniond FromRotationVector(const Eigen::Vector3d& rotation_vector) {
  const double angle = rotation_vector.norm();
  if (angle == 0) return Eigen::Quaterniond::Identity();
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, rotation_vector / angle));
}

// Rotation whose columns are the given axes (right-handed).
inline Eigen::Quaterniond FromAxes(const Eigen::Vector3d& x, const Eigen::Vector3d& y,
                                   const Eigen::Vector3d& z) {
  Eigen::Matrix3d m;
  m << x, y, z;
  return Eigen::Quaterniond(m);
}

// Camera looking straight down from `altitude` above the world origin
// (camera x = world x, camera y = world -y).
inline Rigid3d LookingDown(const Eigen::Vector3d& position) {
  return Rigid3d(FromAxes({1, 0, 0}, {0, -1, 0}, {0, 0, -1}), position);
}

inline Surface Floor(uint64_t seed, double size_m) {
  Surface floor;
  floor.name = "floor";
  floor.type = SurfaceType::kPlane;
  floor.size_x = floor.size_y = size_m;
  floor.texture.type = TextureType::kNatural;
  floor.texture.albedo = {0.45, 0.42, 0.33};  // sand
  floor.texture.contrast = 0.7;
  floor.texture.scale_m = 0.8;
  floor.texture.octaves = 8;
  floor.texture.seed = SplitMix64(seed ^ 0xF1004);
  return floor;
}

inline Surface Checkerboard(const std::string& name, int squares_x, int squares_y,
                            double square_m) {
  Surface board;
  board.name = name;
  board.type = SurfaceType::kPlane;
  board.size_x = (squares_x + 2) * square_m;  // one square of white margin
  board.size_y = (squares_y + 2) * square_m;
  board.texture.type = TextureType::kCheckerboard;
  board.texture.albedo = {0.85, 0.85, 0.85};
  board.texture.albedo_dark = {0.04, 0.04, 0.04};
  board.texture.scale_m = square_m;
  board.texture.squares_x = squares_x;
  board.texture.squares_y = squares_y;
  return board;
}

// The laboratory scenarios of §6.1 and §6.2 (scenario_lab.cc).
Scenario Aquarium(const ScenarioOptions& options);
Scenario LaserTilt(const ScenarioOptions& options);

}  // namespace uwscan::sim::internal
