// Laser profiles: detections triangulated with the refracted camera ray and
// the (bent) light sheet (thesis eq. 5.2 and §4.3), in the camera frame.
#pragma once

#include <Eigen/Core>
#include <string>
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
  int failed = 0;   // detections whose ray missed the sheet or the port
  int grazing = 0;  // detections whose ray grazes the sheet (max_range_error_per_px)
};

// A detection is off by up to a pixel or so. Where the camera ray meets the
// light sheet at a small angle, that moves the triangulated point by a
// large part of its range: such a point is not measured, it is something
// lit far from the line (a particle near the lights, a reflection) that the
// ray carries to where it grazes the sheet, tens of metres away. At 5 % per
// pixel the tank rig at 640x480 keeps points out to some 20 m (at 2 m: 0.6 %
// per pixel).
inline constexpr double kMaxRangeErrorPerPixel = 0.05;

// Triangulates every detection; `camera_from_laser` already includes any
// servo angle. Detections whose ray cannot be formed or misses are counted
// in `failed`, never returned as NaN; those whose range would move by more
// than `max_range_error_per_px` of itself for a one-pixel error (the angle
// of a pixel at the image's centre over the tangent of the ray's angle to
// the sheet) in `grazing` (0: none dropped).
Profile TriangulateProfile(const Camera& camera, const LineProjector& laser,
                           const Rigid3d& camera_from_laser, const std::vector<LaserPoint>& points,
                           int frame = 0, double max_range_error_per_px = kMaxRangeErrorPerPixel);

// Line points whose ray met the light sheet nowhere: none where the rig
// holds the laser that drew the line. Where a fifth or more of a frame's
// `points` (at least kPoseCheckPoints) missed in `profile`, whether the
// inverse of the laser's pose would place nearly all of them (a
// laser_from_camera transform given as camera_from_laser); the pose at
// servo angle `angle_rad`.
inline constexpr size_t kPoseCheckPoints = 20;
bool InverseLaserPoseFits(const Camera& camera, const LineProjector& laser,
                          const Rigid3d& camera_from_laser, double angle_rad,
                          const std::vector<LaserPoint>& points, const Profile& profile,
                          double max_range_error_per_px);
// The warning for `missed` such points of `missed + kept` (empty under 5 %).
std::string MissedSheetWarning(long missed, long kept, bool inverse_fits);

}  // namespace uwscan::laser
