// Ground truth of the laser line (laser_gt.csv): rays of the light sheet
// (x, p1 x^2, 1) in the laser frame, eq. 4.30, intersected with the scene,
// kept where the camera sees the lit side unoccluded, projected exactly.
#include <cmath>

#include "uwscan/sim/renderer.h"
#include "uwscan/sim/renderer_internal.h"

namespace uwscan::sim {

std::vector<LaserPoint> Renderer::LaserGroundTruth(const FrameState& state,
                                                   double spacing_px) const {
  const std::vector<LaserFrame> lasers = MakeLaserFrames(state);
  const Rigid3d& world_from_camera = state.world_from_camera;
  const Rigid3d camera_from_world = world_from_camera.Inverse();
  const Camera& cam = camera();
  std::vector<LaserPoint> points;
  const int samples = 8 * std::max(width_, height_);
  for (const LaserFrame& laser : lasers) {
    const Eigen::Vector3d origin_world = world_from_camera * laser.camera_from_laser.translation;
    const Eigen::Quaterniond world_q_laser =
        world_from_camera.rotation * laser.camera_from_laser.rotation;
    bool have_last = false;
    Eigen::Vector2d last = Eigen::Vector2d::Zero();
    for (int i = 0; i < samples; ++i) {
      const double x = laser.tan_half_fan * (2.0 * (i + 0.5) / samples - 1.0);
      const Eigen::Vector3d direction_world =
          world_q_laser * Eigen::Vector3d(x, laser.p1 * x * x, 1.0).normalized();
      const auto hit =
          config_.scene.Intersect(origin_world, direction_world, 1e-9, config_.render.max_range_m);
      if (!hit) {
        have_last = false;
        continue;
      }
      const Eigen::Vector3d point = camera_from_world * hit->point_world;
      const auto pixel = cam.Project(point, ProjectionMethod::kExact);
      if (!pixel || !cam.InImage(*pixel)) {
        have_last = false;
        continue;
      }
      // Visible: the camera ray through the pixel reaches this very point,
      // and camera and laser look at the same side of the surface.
      const auto ray = cam.BackProject(*pixel);
      if (!ray) continue;
      const Eigen::Vector3d camera_direction_world = world_from_camera.rotation * ray->direction;
      const auto seen =
          config_.scene.Intersect(world_from_camera * ray->origin, camera_direction_world, 1e-9,
                                  config_.render.max_range_m);
      const double tolerance = 1e-6 * std::max(1.0, hit->lambda);
      if (!seen || (seen->point_world - hit->point_world).norm() > tolerance ||
          hit->normal_world.dot(direction_world) * hit->normal_world.dot(camera_direction_world) <=
              0) {
        have_last = false;
        continue;
      }
      if (have_last && (*pixel - last).norm() < spacing_px) continue;
      points.push_back(LaserPoint{laser.source, *pixel, point});
      last = *pixel;
      have_last = true;
    }
  }
  return points;
}

}  // namespace uwscan::sim
