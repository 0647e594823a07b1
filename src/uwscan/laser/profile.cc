#include "uwscan/laser/profile.h"

#include <Eigen/Geometry>

namespace uwscan::laser {

Rigid3d CameraFromLaserAtAngle(const Rigid3d& camera_from_laser, double angle_rad) {
  const Eigen::Quaterniond servo(Eigen::AngleAxisd(angle_rad, Eigen::Vector3d::UnitX()));
  return camera_from_laser * Rigid3d(servo, Eigen::Vector3d::Zero());
}

Profile TriangulateProfile(const Camera& camera, const LineProjector& laser,
                           const Rigid3d& camera_from_laser, const std::vector<LaserPoint>& points,
                           int frame) {
  LineProjector posed = laser;
  posed.camera_from_laser = camera_from_laser;
  Profile profile;
  profile.frame = frame;
  profile.points.reserve(points.size());
  for (const auto& p : points) {
    const Eigen::Vector2d pixel(p.u, p.v);
    const auto ray = camera.BackProject(pixel);
    const auto point = ray ? posed.Triangulate(*ray) : std::nullopt;
    if (!point || !point->allFinite()) {
      ++profile.failed;
      continue;
    }
    profile.points.push_back({*point, pixel, p.strength});
  }
  return profile;
}

}  // namespace uwscan::laser
