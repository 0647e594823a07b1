// Laser profiles: detections triangulated with the refracted camera ray and
// the (bent) light sheet (thesis eq. 5.2 and §4.3), in the camera frame.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "uwscan/laser/detector.h"
#include "uwscan/sensor/rig.h"

namespace uwscan::laser {

// The laser's pose when its servo stands at `angle_rad`: the servo turns the
// projector about its own x axis (the direction along the line), so the
// light sheet sweeps across the scene. camera_from_laser(0) is the rig's.
Rigid3d CameraFromLaserAtAngle(const Rigid3d& camera_from_laser, double angle_rad);

struct ProfilePoint {
  Eigen::Vector3d point_in_camera;
  Eigen::Vector2d pixel;
  float strength = 0.0f;
};

struct Profile {
  int frame = 0;
  std::vector<ProfilePoint> points;
  int failed = 0;  // detections whose ray missed the sheet or the port
};

// Triangulates every detection; `camera_from_laser` already includes any
// servo angle. Detections whose ray cannot be formed or misses are counted
// in `failed`, never returned as NaN.
Profile TriangulateProfile(const Camera& camera, const LineProjector& laser,
                           const Rigid3d& camera_from_laser, const std::vector<LaserPoint>& points,
                           int frame = 0);

}  // namespace uwscan::laser
