#include "uwscan/fusion/surface_model.h"

#include <gtest/gtest.h>

#include "uwscan/sim/scenario.h"

namespace uwscan::fusion {
namespace {

// Profiles of a laser sweeping a tank floor (from the simulator's true laser
// points) give rays through the swept region their true depth.
TEST(SurfaceModel, RaysMeetTheSweptSurface) {
  sim::ScenarioOptions options;
  options.width = 320;
  options.height = 240;
  options.frames = 12;
  sim::Scenario scenario = sim::MakeScenario("tank-target", options);
  scenario.config.scene.Prepare();
  const sim::Renderer renderer(scenario.config);
  const sim::Trajectory trajectory(scenario.motion);
  const Camera& camera = renderer.camera();
  const Rigid3d world_from_first = trajectory.WorldFromCamera(0.0);
  SurfaceModelOptions options_local;
  options_local.extrapolate_plane = false;
  SurfaceModel surface(camera, world_from_first, options_local);
  for (int frame = 0; frame < scenario.frames; ++frame) {
    const sim::FrameState state = scenario.FrameAt(trajectory, frame);
    laser::Profile profile;
    for (const auto& p : renderer.LaserGroundTruth(state)) {
      profile.points.push_back({p.point_in_camera, p.pixel, 1.0f});
    }
    surface.AddProfile(state.world_from_camera, profile);
  }
  ASSERT_GT(surface.size(), 500);
  int hits = 0, misses = 0;
  double worst = 0.0;
  for (int v = 10; v < camera.height; v += 20) {
    for (int u = 10; u < camera.width; u += 20) {
      const auto ray = camera.BackProject(Eigen::Vector2d(u, v));
      ASSERT_TRUE(ray.has_value());
      const Eigen::Vector3d origin = world_from_first * ray->origin;
      const Eigen::Vector3d direction = world_from_first.rotation * ray->direction;
      const auto truth = scenario.config.scene.Intersect(origin, direction);
      const auto hit = surface.Intersect(origin, direction);
      if (!hit) {
        ++misses;
        continue;
      }
      ++hits;
      ASSERT_TRUE(truth.has_value());
      worst = std::max(worst, (hit->point - truth->point_world).norm());
    }
  }
  EXPECT_GT(hits, 20);
  EXPECT_LT(worst, 0.008) << hits << " hits";  // the 5 mm board edge is smoothed over
  EXPECT_GT(misses, 0);                        // not swept yet: no depth rather than a guess
}

}  // namespace
}  // namespace uwscan::fusion
