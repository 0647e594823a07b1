#include "uwscan/vo/geometric_solvers.h"

#include <gtest/gtest.h>

#include <random>

#include "uwscan/eval/port_analysis.h"
#include "uwscan/vo/cost_functions.h"

namespace uwscan::vo {
namespace {

// A flat-port camera whose port is far from the optimal air gap (eq. 4.27),
// so that the pinhole approximation is visibly biased.
Camera DeepPortCamera() {
  Camera camera = Camera::Flat1();
  camera.port.d_air = 0.03;
  return camera;
}

struct Scene {
  std::vector<Eigen::Vector3d> points_world;
  std::vector<Eigen::Vector2d> pixels;  // in the camera at camera_from_world
  std::vector<Ray> rays;                // back-projected pixels (camera frame)
};

// Points on a bumpy floor 1.5-2.5 m in front of the camera, projected
// exactly through the port plus Gaussian pixel noise.
Scene MakeScene(const Camera& camera, const Rigid3d& camera_from_world, int count, double noise_px,
                unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, camera.width - 1), v(0, camera.height - 1),
      depth(1.5, 2.5);
  std::normal_distribution<double> noise(0.0, noise_px);
  Scene scene;
  const Rigid3d world_from_camera = camera_from_world.Inverse();
  while (int(scene.pixels.size()) < count) {
    const Eigen::Vector2d pixel(u(rng), v(rng));
    const auto ray = camera.BackProject(pixel);
    if (!ray) continue;
    const Eigen::Vector3d point_camera = ray->At(depth(rng) / ray->direction.z());
    const Eigen::Vector2d noisy = pixel + Eigen::Vector2d(noise(rng), noise(rng));
    scene.points_world.push_back(world_from_camera * point_camera);
    scene.pixels.push_back(noisy);
    scene.rays.push_back(*camera.BackProject(noisy));
  }
  return scene;
}

double RotationErrorDeg(const Rigid3d& a, const Rigid3d& b) {
  return Eigen::AngleAxisd(a.rotation.inverse() * b.rotation).angle() * 180.0 / M_PI;
}

Rigid3d SomePose() {
  return Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d(1, 2, 3).normalized())),
                 Eigen::Vector3d(0.3, -0.1, 0.2));
}

TEST(AbsolutePose, GeneralisedP3PIsExactOnRefractedRays) {
  const Camera camera = DeepPortCamera();
  const Rigid3d truth = SomePose();
  const Scene scene = MakeScene(camera, truth, 100, 0.0, 1);
  AbsolutePoseOptions options;
  options.solver = AbsolutePoseSolver::kGP3P;
  const AbsolutePoseResult gp3p = EstimateAbsolutePose(scene.rays, scene.points_world, options);
  ASSERT_TRUE(gp3p.success);
  EXPECT_EQ(gp3p.num_inliers, 100);
  EXPECT_LT((gp3p.camera_from_world.translation - truth.translation).norm(), 1e-6);
  EXPECT_LT(RotationErrorDeg(gp3p.camera_from_world, truth), 1e-5);
  // The central P3P on the same rays ignores their origins on the port:
  // biased by millimetres.
  options.solver = AbsolutePoseSolver::kP3P;
  options.threshold_rad = 0.02;
  const AbsolutePoseResult p3p = EstimateAbsolutePose(scene.rays, scene.points_world, options);
  ASSERT_TRUE(p3p.success);
  EXPECT_GT((p3p.camera_from_world.translation - truth.translation).norm(), 1e-4);
}

TEST(AbsolutePose, RansacRejectsOutliers) {
  const Camera camera = DeepPortCamera();
  const Rigid3d truth = SomePose();
  Scene scene = MakeScene(camera, truth, 100, 0.3, 2);
  for (int i = 0; i < 30; ++i) scene.points_world[size_t(i)] += Eigen::Vector3d(0.2, -0.1, 0.1);
  const AbsolutePoseResult result = EstimateAbsolutePose(scene.rays, scene.points_world);
  ASSERT_TRUE(result.success);
  for (int i = 0; i < 30; ++i) EXPECT_FALSE(result.inliers[size_t(i)]) << i;
  EXPECT_GE(result.num_inliers, 65);
  EXPECT_LT((result.camera_from_world.translation - truth.translation).norm(), 5e-3);
}

TEST(RelativePose, FivePointRecoversMotion) {
  const Camera camera = DeepPortCamera();
  const Rigid3d cam2_from_cam1(
      Eigen::Quaterniond(Eigen::AngleAxisd(0.05, Eigen::Vector3d(0, 1, 0.3).normalized())),
      Eigen::Vector3d(0.3, 0.05, 0.02));
  const Scene scene = MakeScene(camera, Rigid3d(), 200, 0.0, 3);
  std::vector<Ray> rays2;
  for (const auto& p : scene.points_world) {
    rays2.push_back(*camera.BackProject(*camera.Project(cam2_from_cam1 * p)));
  }
  RelativePoseOptions options;
  options.threshold_rad = 3.0 / 785.0;  // the central approximation is biased
  const RelativePoseResult result = EstimateRelativePose(scene.rays, rays2, options);
  ASSERT_TRUE(result.success);
  EXPECT_GE(result.num_inliers, 180);
  EXPECT_LT(RotationErrorDeg(result.camera2_from_camera1, cam2_from_cam1), 0.5);
  const double direction_error_deg =
      std::acos(std::clamp(
          result.camera2_from_camera1.translation.dot(cam2_from_cam1.translation.normalized()),
          -1.0, 1.0)) *
      180.0 / M_PI;
  EXPECT_LT(direction_error_deg, 2.0);
}

TEST(Triangulation, IntersectsRefractedRaysExactly) {
  const Camera camera = DeepPortCamera();
  const Rigid3d cam2_from_world(
      Eigen::Quaterniond(Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitY())),
      Eigen::Vector3d(-0.3, 0, 0));
  const Scene scene = MakeScene(camera, Rigid3d(), 50, 0.0, 4);
  const Rigid3d world_from_cam2 = cam2_from_world.Inverse();
  for (size_t i = 0; i < scene.points_world.size(); ++i) {
    const auto pixel2 = camera.Project(cam2_from_world * scene.points_world[i]);
    if (!pixel2 || !camera.InImage(*pixel2)) continue;
    const Ray ray2 = *camera.BackProject(*pixel2);
    const std::vector<Ray> rays = {
        scene.rays[i], {world_from_cam2 * ray2.origin, world_from_cam2.rotation * ray2.direction}};
    const auto point = TriangulateRays(rays);
    ASSERT_TRUE(point.has_value());
    EXPECT_LT((*point - scene.points_world[i]).norm(), 1e-7);
    EXPECT_GT(MaxRayAngle(rays), 0.05);
  }
  // Parallel rays do not triangulate.
  const Ray a{Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ()};
  const Ray b{Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitZ()};
  EXPECT_FALSE(TriangulateRays({a, b}).has_value());
  // A point behind a ray is rejected.
  const Ray c{Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0, 0, 1)};
  const Ray d{Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(1, 0, 1).normalized()};
  EXPECT_FALSE(TriangulateRays({c, d}).has_value());
}

}  // namespace
}  // namespace uwscan::vo
