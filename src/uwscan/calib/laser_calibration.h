// Line projector calibration (thesis §4.4 "Line Projector Refinement",
// eq. 4.30; §6.2; servo sweep §6.5): laser points on boards of known pose ->
// least-squares plane with RANSAC -> refinement of the projector model
// (pose and bend p1) on the sheet residual of eq. 4.30.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "uwscan/geometry/rigid3d.h"
#include "uwscan/sensor/camera.h"
#include "uwscan/sensor/rig.h"

namespace uwscan {

// One image of the board with the laser on.
struct LaserView {
  std::string name;
  Rigid3d camera_from_board;
  std::vector<Eigen::Vector2d> laser_pixels;
  double servo_angle_rad = 0.0;  // servo variant only
};

// The servo axis in the camera frame: the laser turns by +angle (right hand)
// about `direction` through `point`.
struct ServoAxis {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitY();
};

struct LaserCalibrationOptions {
  double ransac_threshold_m = 0.002;
  int ransac_iterations = 300;
  unsigned seed = 1;
  bool refine_bend = true;  // free p1 (eq. 4.30); false keeps a plane
  // Where the projector sits, roughly (e.g. from the mechanical design or
  // the input rig); its translation is projected onto the fitted sheet as
  // the projector centre. Without it the centre is the foot of the
  // perpendicular from the camera centre.
  std::optional<Rigid3d> nominal_camera_from_laser;
  int min_points = 20;
  double min_depth_spread_m = 0.05;  // points must span this much across the views' planes
  void Check() const;
};

struct LaserCalibrationResult {
  LineProjector laser;
  Eigen::Vector3d plane_normal = Eigen::Vector3d::UnitX();  // RANSAC + LS plane n.X = d
  double plane_d = 0.0;
  int points = 0;
  int inliers = 0;
  double plane_rms_m = 0.0;      // inlier distance to the LS plane
  double sheet_rms_m = 0.0;      // inlier distance to the refined (bent) sheet, approx.
  double baseline_m = 0.0;       // camera centre to the sheet's tangent plane at its centre line
  double sheet_angle_deg = 0.0;  // angle between the sheet normal and the camera x axis
  int iterations = 0;
  std::vector<int> view_points;  // laser points per view that hit the board
};

// Camera rays of laser pixels intersected with the board plane (refracted
// rays for a flat port). Pixels whose ray misses the plane are skipped.
std::vector<Eigen::Vector3d> LaserPointsOnBoard(const Camera& camera,
                                                const Rigid3d& camera_from_board,
                                                const std::vector<Eigen::Vector2d>& pixels);

// The core: fits the projector to 3D points on the sheet (camera frame).
LaserCalibrationResult FitLaserProjector(const std::vector<Eigen::Vector3d>& points_in_camera,
                                         const LaserCalibrationOptions& options);

// Boards at two or more distances, or (servo != nullptr) one sweep over a
// fixed board: profiles are rotated back about the servo axis by their
// angles, and the result is the projector at servo angle 0.
LaserCalibrationResult CalibrateLaser(const Camera& camera, const std::vector<LaserView>& views,
                                      const LaserCalibrationOptions& options,
                                      const ServoAxis* servo = nullptr);

}  // namespace uwscan
