// A rig: cameras with their extrinsics and line lasers. `camera_from_laser`
// is relative to the first camera; other cameras reach a laser through
// rig_from_camera.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "uwscan/sensor/camera.h"

namespace uwscan {

struct LineProjector {
  std::string name = "laser0";
  Rigid3d camera_from_laser;
  double p1 = 0.0;  // bend, eq. 4.30
  double wavelength_nm = 532.0;

  // Intersects a camera-frame ray with the (bent) light sheet.
  std::optional<Eigen::Vector3d> Triangulate(const Ray& ray) const;
  // The sine of the angle at which a camera-frame ray direction meets the
  // sheet at `point_in_camera` (on it): a point's range moves by the
  // cotangent of that angle times its range per radian the ray turns.
  double SineToSheet(const Eigen::Vector3d& direction,
                     const Eigen::Vector3d& point_in_camera) const;
  // Signed residual of eq. 4.30 for a camera-frame point; nullopt behind it.
  std::optional<double> SheetResidual(const Eigen::Vector3d& point_in_camera) const;
  void Check(const std::string& context) const;
};

struct Rig {
  std::vector<Camera> cameras;
  std::vector<LineProjector> lasers;
  std::string source;  // the file it was read from, named in its errors ("" if none)

  // Throws uwscan::Error if no camera has this name; empty name = first camera.
  const Camera& CameraByName(const std::string& name) const;
  const LineProjector& LaserByName(const std::string& name) const;
  // camera_from_laser for any camera of the rig.
  Rigid3d CameraFromLaser(size_t camera_index, size_t laser_index) const;
  // to_from_from between two cameras of the rig, through rig_from_camera.
  Rigid3d CameraFromCamera(size_t to_index, size_t from_index) const;
  // The same rig seen from another camera: that camera and that laser come
  // first (the defaults of every command), camera_from_laser re-expressed
  // relative to the new first camera, the others in their order.
  Rig Reordered(size_t first_camera, size_t first_laser) const;
  void Check(const std::string& context) const;
};

}  // namespace uwscan
