#include "uwscan/vo/geometric_solvers.h"

#include <gtest/gtest.h>

#include <opengv/relative_pose/NoncentralRelativeAdapter.hpp>
#include <opengv/relative_pose/methods.hpp>
#include <random>

#include "uwscan/eval/port_analysis.h"
#include "uwscan/sensor/triangulation.h"
#include "uwscan/vo/cost_functions.h"
#include "uwscan/vo/windowed_bundle_adjuster.h"

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

double DirectionErrorDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 / M_PI;
}

// Which initialisation for a flat port (issue 6)? On refracted
// correspondences with 0.3 px noise: (a) the five-point algorithm on the
// central approximation, (b) the same refined by the two-view bundle
// adjustment with the exact refractive residual (what the odometry does),
// (c) OpenGV's generalised 17-point solver on the rays with their origins.
TEST(RelativePose, RefinedFivePointBeatsCentralAndSeventeenPoint) {
  const Camera camera = DeepPortCamera();
  const Rigid3d cam2_from_cam1(
      Eigen::Quaterniond(Eigen::AngleAxisd(0.04, Eigen::Vector3d(0.2, 1, 0.1).normalized())),
      Eigen::Vector3d(-0.25, 0.04, 0.02));
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 0.3);
  const Scene scene = MakeScene(camera, Rigid3d(), 150, 0.3, 12);
  std::vector<Ray> rays1, rays2;
  std::vector<Eigen::Vector2d> pixels1, pixels2;
  std::vector<Eigen::Vector3d> points;
  for (size_t i = 0; i < scene.points_world.size(); ++i) {
    const auto pixel = camera.Project(cam2_from_cam1 * scene.points_world[i]);
    if (!pixel || !camera.InImage(*pixel)) continue;
    const Eigen::Vector2d noisy = *pixel + Eigen::Vector2d(noise(rng), noise(rng));
    rays1.push_back(scene.rays[i]);
    rays2.push_back(*camera.BackProject(noisy));
    pixels1.push_back(scene.pixels[i]);
    pixels2.push_back(noisy);
    points.push_back(scene.points_world[i]);
  }
  ASSERT_GT(rays1.size(), 100u);

  // (a) five-point, central approximation.
  RelativePoseOptions options;
  options.threshold_rad = 3.0 / 785.0;
  const RelativePoseResult five = EstimateRelativePose(rays1, rays2, options);
  ASSERT_TRUE(five.success);
  const double rot_a = RotationErrorDeg(five.camera2_from_camera1, cam2_from_cam1);
  const double dir_a =
      DirectionErrorDeg(five.camera2_from_camera1.translation, cam2_from_cam1.translation);

  // (b) refined with the refractive two-view BA at metric baseline length.
  SparseMap map;
  Keyframe kf0, kf1;
  kf1.id = 1;
  kf1.camera_from_world = five.camera2_from_camera1;
  kf1.camera_from_world.translation *= cam2_from_cam1.translation.norm();
  const Rigid3d world_from_kf1 = kf1.camera_from_world.Inverse();
  for (size_t i = 0; i < rays1.size(); ++i) {
    const Ray r2{world_from_kf1 * rays2[i].origin, world_from_kf1.rotation * rays2[i].direction};
    const auto point = TriangulateRays({rays1[i], r2});
    if (!point) continue;
    map.points[i + 1] = {i + 1, *point, 2};
    kf0.observations[i + 1] = pixels1[i];
    kf1.observations[i + 1] = pixels2[i];
  }
  map.keyframes = {kf0, kf1};
  BundleAdjustmentOptions ba;
  ba.max_iterations = 50;
  ba.max_solver_time_s = 10;
  AdjustWindow(camera, ba, &map, /*two_view_init=*/true);
  const Rigid3d refined = map.keyframes[1].camera_from_world;
  const double rot_b = RotationErrorDeg(refined, cam2_from_cam1);
  const double dir_b = DirectionErrorDeg(refined.translation, cam2_from_cam1.translation);

  // (c) generalised 17-point (Li et al. 2008) on the refracted rays.
  opengv::bearingVectors_t b1, b2;
  opengv::translations_t offsets;
  opengv::rotations_t rotations;
  std::vector<int> c1, c2;
  const int n = int(rays1.size());
  for (int i = 0; i < n; ++i) {
    b1.push_back(rays1[size_t(i)].direction);
    b2.push_back(rays2[size_t(i)].direction);
    c1.push_back(i);
    c2.push_back(n + i);
  }
  for (int i = 0; i < n; ++i) offsets.push_back(rays1[size_t(i)].origin);
  for (int i = 0; i < n; ++i) offsets.push_back(rays2[size_t(i)].origin);
  rotations.assign(size_t(2 * n), Eigen::Matrix3d::Identity());
  opengv::relative_pose::NoncentralRelativeAdapter adapter(b1, b2, c1, c2, offsets, rotations);
  const opengv::transformation_t cam1_from_cam2 = opengv::relative_pose::seventeenpt(adapter);
  const Rigid3d seventeen =
      Rigid3d(Eigen::Quaterniond(Eigen::Matrix3d(cam1_from_cam2.block<3, 3>(0, 0))),
              cam1_from_cam2.col(3))
          .Inverse();
  const double rot_c = RotationErrorDeg(seventeen, cam2_from_cam1);
  const double dir_c = DirectionErrorDeg(seventeen.translation, cam2_from_cam1.translation);

  printf(
      "rotation / translation-direction error (deg): five-point %.4f / %.3f, refined %.4f / "
      "%.3f, 17-point %.4f / %.3f (17-point baseline %.3f m, true %.3f m)\n",
      rot_a, dir_a, rot_b, dir_b, rot_c, dir_c, seventeen.translation.norm(),
      cam2_from_cam1.translation.norm());
  EXPECT_LT(rot_b, 0.5 * rot_a);
  EXPECT_LT(dir_b, dir_a);
  EXPECT_LT(rot_b, 0.1);  // noise-limited (0.3 px)
  EXPECT_LT(rot_b, rot_c);
  EXPECT_LT(dir_b, dir_c);
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
