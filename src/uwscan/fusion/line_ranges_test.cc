#include "uwscan/fusion/line_ranges.h"

#include <gtest/gtest.h>

#include <cmath>

#include "uwscan/sim/renderer.h"
#include "uwscan/sim/scenario.h"
#include "uwscan/sim/testing.h"

namespace uwscan::fusion {
namespace {

// One frame of the seabed transect: map points on the true sea floor at
// pixels across the laser line (0-12 px from it) and far from it. Those
// whose ray passes within max_offset_m of a true laser point get the range
// of the scene along their own ray, within the sigma they claim; the
// others get none; a point on a surface 40 % farther than the laser
// measures (another surface on the ray) is not constrained either.
TEST(LineRanges, MapPointsMeetingTheLineGetTheirRange) {
  const sim::Scenario scenario = sim::testing::SmallScenario("seabed-transect", 10);
  const sim::Renderer renderer(scenario.config);
  const sim::Trajectory trajectory(scenario.motion);
  const Camera& camera = renderer.camera();
  const sim::FrameState state = scenario.FrameAt(trajectory, 3);
  const Rigid3d camera_from_world = state.world_from_camera.Inverse();
  laser::Profile profile;
  for (const auto& p : renderer.LaserGroundTruth(state)) {
    profile.points.push_back({p.point_in_camera, p.pixel, 1.0f});
  }
  ASSERT_GT(profile.points.size(), 100u);

  // Map points on both sides of the line, at every 10th of its pixels.
  const Eigen::Vector2d along =
      (profile.points.back().pixel - profile.points.front().pixel).normalized();
  const Eigen::Vector2d across(-along.y(), along.x());
  vo::SparseMap map;
  std::unordered_map<uint64_t, double> true_range, offset_px;
  auto add_point = [&](const Eigen::Vector2d& pixel, double scale, double offset) {
    const auto ray = camera.BackProject(pixel);
    if (!ray) return uint64_t(0);
    const Eigen::Vector3d origin = state.world_from_camera * ray->origin;
    const Eigen::Vector3d direction = state.world_from_camera.rotation * ray->direction;
    const auto hit = scenario.config.scene.Intersect(origin, direction);
    if (!hit) return uint64_t(0);
    const uint64_t id = map.points.size() + 1;
    const double range = (hit->point_world - origin).norm();
    map.points[id] = {id, origin + scale * range * direction, 2};
    true_range[id] = range;
    offset_px[id] = offset;
    return id;
  };
  for (size_t i = 0; i < profile.points.size(); i += 10) {
    for (double offset : {0.0, 2.0, -3.0, 12.0, -40.0}) {
      add_point(profile.points[i].pixel + offset * across, 1.0, offset);
    }
  }
  const uint64_t behind = add_point(profile.points[profile.points.size() / 2].pixel, 1.4, 0.0);
  ASSERT_NE(behind, 0u);
  const uint64_t slightly_off =
      add_point(profile.points[profile.points.size() / 3].pixel, 1.1, 0.0);
  ASSERT_NE(slightly_off, 0u);

  const auto ranges = LineRangeConstraints(camera, map, camera_from_world, profile);
  std::unordered_map<uint64_t, const vo::RangeConstraint*> by_id;
  for (const auto& r : ranges) by_id[r.point_id] = &r;
  int on_line = 0, on_line_found = 0, found = 0;
  double sum_squared_normalised = 0.0;
  for (const auto& [id, point] : map.points) {
    const auto it = by_id.find(id);
    if (id == behind) {
      EXPECT_EQ(it, by_id.end()) << "a point 40 % behind the laser's surface";
      continue;
    }
    const double offset = std::abs(offset_px.at(id));
    if (offset >= 12.0) {  // 12 px ~ 7 cm on the floor at 2 m
      EXPECT_EQ(it, by_id.end()) << "a point " << offset << " px from the line";
      continue;
    }
    if (offset == 0.0) {
      ++on_line;
      on_line_found += it != by_id.end();
    }
    if (it == by_id.end()) continue;
    const vo::RangeConstraint& r = *it->second;
    // The true range: the point's own ray (pixel it projects to) to the floor.
    const double error = r.range_m - true_range.at(id);
    EXPECT_LT(std::abs(error), 3.0 * r.sigma_m) << offset << " px, sigma " << r.sigma_m;
    sum_squared_normalised += error * error / (r.sigma_m * r.sigma_m);
    ++found;
    if (offset == 0.0) {
      EXPECT_NEAR(r.range_m, true_range.at(id), 1e-3);
    }
    ASSERT_TRUE(r.ray_origin_camera.has_value());
    const auto ray = camera.BackProject(*camera.Project(camera_from_world * point.position_world));
    EXPECT_LT((*r.ray_origin_camera - ray->origin).norm(), 1e-9);
  }
  // The sigmas are honest: normalised errors of about unit spread, not less
  // (a constraint much tighter than its error would bias the scale).
  printf("%d constraints (%d on the line), rms of error/sigma %.2f\n", found, on_line,
         std::sqrt(sum_squared_normalised / found));
  ASSERT_GT(found, on_line);
  EXPECT_LT(std::sqrt(sum_squared_normalised / found), 1.5);
  EXPECT_GT(on_line, 10);
  EXPECT_EQ(on_line_found, on_line);
  // 10 % off: measured, so the bundle adjustment can pull it onto the floor.
  ASSERT_TRUE(by_id.count(slightly_off));
  EXPECT_NEAR(by_id.at(slightly_off)->range_m, true_range.at(slightly_off), 1e-3);
}

}  // namespace
}  // namespace uwscan::fusion
