#include "uwscan/geometry/fits.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

namespace uwscan {
namespace {

TEST(Fits, PlaneRecoversNormalAndNoise) {
  std::mt19937 rng(5);
  std::normal_distribution<double> noise(0.0, 0.001);
  std::uniform_real_distribution<double> coordinate(-0.5, 0.5);
  const Eigen::Vector3d normal = Eigen::Vector3d(0.1, -0.2, 1.0).normalized();
  const Eigen::Vector3d u = normal.unitOrthogonal(), v = normal.cross(u);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 5000; ++i) {
    points.push_back(Eigen::Vector3d(0, 0, 2) + coordinate(rng) * u + coordinate(rng) * v +
                     noise(rng) * normal);
  }
  const auto fit = FitPlane(points);
  ASSERT_TRUE(fit.has_value());
  EXPECT_GT(std::abs(fit->normal.dot(normal)), 1.0 - 1e-5);
  EXPECT_NEAR(fit->rms, 0.001, 0.00005);
  EXPECT_FALSE(FitPlane({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 3, 3}}).has_value());
}

TEST(Fits, CylinderRecoversAxisAndRadius) {
  std::mt19937 rng(9);
  std::normal_distribution<double> noise(0.0, 0.0005);
  std::uniform_real_distribution<double> along(-0.4, 0.4), angle(-1.2, 1.2);  // a visible arc only
  const Eigen::Vector3d direction = Eigen::Vector3d(1.0, 0.05, 0.02).normalized();
  const Eigen::Vector3d centre(0.1, 0.3, 2.0);
  const Eigen::Vector3d e1 = direction.unitOrthogonal(), e2 = direction.cross(e1);
  const double radius = 0.15;
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 3000; ++i) {
    const double a = angle(rng);
    // The arc faces the camera at the origin: -z side of the shaft.
    const Eigen::Vector3d radial = std::cos(a) * (-e2) + std::sin(a) * e1;
    points.push_back(centre + along(rng) * direction + (radius + noise(rng)) * radial);
  }
  const auto fit = FitCylinder(points, Eigen::Vector3d(1, 0, 0), 0.1, Eigen::Vector3d(0, 0, 1));
  ASSERT_TRUE(fit.has_value());
  EXPECT_NEAR(fit->radius, radius, 0.001);
  EXPECT_GT(std::abs(fit->axis_direction.dot(direction)), 1.0 - 1e-5);
  const Eigen::Vector3d offset = fit->axis_point - centre;
  EXPECT_LT((offset - offset.dot(direction) * direction).norm(), 0.002);
  EXPECT_NEAR(fit->rms, 0.0005, 0.00005);
}

}  // namespace
}  // namespace uwscan
