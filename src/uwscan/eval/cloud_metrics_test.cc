#include "uwscan/eval/cloud_metrics.h"

#include <gtest/gtest.h>

#include <random>

#include "uwscan/sim/scene.h"

namespace uwscan {
namespace {

// A plane seen from 2 m, the cloud on it with 0.5 mm noise plus a few gross
// outliers (mixed pixels, 0.3 m off along their rays): the plain fit is
// ruined by them, the robust fit drops exactly them and measures the noise.
TEST(CloudMetrics, RobustFitDropsGrossOutliersOnly) {
  Camera camera;
  camera.width = 320;
  camera.height = 240;
  camera.intrinsics = {300.0, 300.0, 159.5, 119.5};
  sim::Scene scene;
  sim::Surface floor;
  floor.name = "floor";
  floor.size_x = floor.size_y = 10.0;
  scene.surfaces = {floor};
  // Camera 2 m above the floor, looking down (camera z = -world z).
  Eigen::Matrix3d down;
  down << 1, 0, 0, 0, -1, 0, 0, 0, -1;
  const Rigid3d world_from_camera(Eigen::Quaterniond(down), Eigen::Vector3d(0, 0, 2));
  const std::map<int, Rigid3d> poses = {{0, world_from_camera}};
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.0005);
  std::vector<CloudPoint> cloud;
  int outliers = 0;
  for (int v = 10; v < 230; v += 4) {
    for (int u = 10; u < 310; u += 4) {
      const auto ray = camera.BackProject(Eigen::Vector2d(u, v));
      ASSERT_TRUE(ray.has_value());
      const double lambda = 2.0 / ray->direction.z();
      const bool outlier = cloud.size() % 97 == 50;
      outliers += outlier;
      CloudPoint point;
      point.position = world_from_camera * (ray->origin + (lambda + (outlier ? 0.3 : 0.0)) *
                                                             ray->direction) +
                       Eigen::Vector3d(0, 0, noise(rng));
      cloud.push_back(point);
    }
  }
  ASSERT_GT(outliers, 3);
  const CloudAccuracy accuracy = EvaluateCloud(cloud, poses, poses, camera, scene);
  const SurfaceAccuracy* result = accuracy.Surface("floor");
  ASSERT_NE(result, nullptr);
  EXPECT_GT(result->fit_rms_m, 0.005);
  EXPECT_EQ(result->robust_outliers, outliers);
  EXPECT_NEAR(result->robust_fit_rms_m, 0.0005, 0.0001);
}

}  // namespace
}  // namespace uwscan
