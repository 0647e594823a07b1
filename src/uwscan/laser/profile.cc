#include "uwscan/laser/profile.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace uwscan::laser {

Rigid3d CameraFromLaserAtAngle(const Rigid3d& camera_from_laser, double angle_rad) {
  const Eigen::Quaterniond servo(Eigen::AngleAxisd(angle_rad, Eigen::Vector3d::UnitX()));
  return camera_from_laser * Rigid3d(servo, Eigen::Vector3d::Zero());
}

namespace {

// The angle between the rays of the image centre's pixel and its neighbour.
double PixelAngle(const Camera& camera) {
  const Eigen::Vector2d centre(0.5 * camera.width, 0.5 * camera.height);
  const auto a = camera.BackProject(centre);
  const auto b = camera.BackProject(centre + Eigen::Vector2d(1.0, 0.0));
  if (!a || !b) return 0.0;
  return std::atan2(a->direction.cross(b->direction).norm(), a->direction.dot(b->direction));
}

}  // namespace

Profile TriangulateProfile(const Camera& camera, const LineProjector& laser,
                           const Rigid3d& camera_from_laser, const std::vector<LaserPoint>& points,
                           int frame, double max_range_error_per_px) {
  LineProjector posed = laser;
  posed.camera_from_laser = camera_from_laser;
  Profile profile;
  profile.frame = frame;
  profile.points.reserve(points.size());
  // Per radian the ray turns, the range moves by cot(angle to the sheet) of itself.
  const double max_cotangent = max_range_error_per_px > 0.0 && !points.empty()
                                   ? max_range_error_per_px / std::max(PixelAngle(camera), 1e-12)
                                   : 0.0;
  for (const auto& p : points) {
    const Eigen::Vector2d pixel(p.u, p.v);
    const auto ray = camera.BackProject(pixel);
    const auto point = ray ? posed.Triangulate(*ray) : std::nullopt;
    if (!point || !point->allFinite()) {
      ++profile.failed;
      continue;
    }
    if (max_cotangent > 0.0) {
      const double sine = posed.SineToSheet(ray->direction, *point);
      if (!(sine * max_cotangent >= std::sqrt(1.0 - std::min(sine * sine, 1.0)))) {
        ++profile.grazing;
        continue;
      }
    }
    profile.points.push_back({*point, pixel, p.strength});
  }
  return profile;
}

bool InverseLaserPoseFits(const Camera& camera, const LineProjector& laser,
                          const Rigid3d& camera_from_laser, double angle_rad,
                          const std::vector<LaserPoint>& points, const Profile& profile,
                          double max_range_error_per_px) {
  const double found = static_cast<double>(points.size());
  if (points.size() < kPoseCheckPoints || profile.failed < 0.2 * found) return false;
  const Profile inverse = TriangulateProfile(
      camera, laser, CameraFromLaserAtAngle(camera_from_laser.Inverse(), angle_rad), points,
      profile.frame, max_range_error_per_px);
  return inverse.failed + inverse.grazing <= 0.02 * found;
}

std::string MissedSheetWarning(long missed, long kept, bool inverse_fits) {
  if (missed <= 0 || missed < 0.05 * (missed + kept)) return "";
  return std::to_string(missed) + " line point(s) (" +
         std::to_string(static_cast<int>(std::lround(100.0 * missed / (missed + kept)))) +
         " %) met the laser's light sheet nowhere in front of the camera and are left out: " +
         (inverse_fits
              ? "the laser's pose in rig.yaml looks inverted, as its inverse places every point "
                "of the first frame with a line (a laser_from_camera transform given as "
                "camera_from_laser?)"
              : "the laser's pose or bend in rig.yaml does not match the line seen (another "
                "laser's calibration? `uwscan calibrate laser` measures it)");
}

}  // namespace uwscan::laser
