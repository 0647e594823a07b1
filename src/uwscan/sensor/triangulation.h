// Where rays meet: the triangulation shared by the odometry (map points)
// and the laser stage (scene texture matched between frames).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "uwscan/sensor/camera.h"

namespace uwscan {

// Least-squares intersection of >= 2 rays in one frame (minimises the sum
// of squared perpendicular distances); nullopt if the rays are (nearly)
// parallel or the point lies behind a ray origin.
std::optional<Eigen::Vector3d> TriangulateRays(const std::vector<Ray>& rays);

}  // namespace uwscan
