#include "uwscan/sensor/line_projector.h"

#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "uwscan/sensor/rig.h"
#include "uwscan/util/jacobian_check.h"

namespace uwscan {
namespace {

// A laser 0.3 m to the right of the camera, its sheet turned towards the
// camera's optical axis (the thesis set-up, §5.3).
LineProjector TestLaser(double p1) {
  LineProjector laser;
  // Laser x along the camera's y (a vertical line), z forward, yawed 10 deg inwards.
  Eigen::Matrix3d rotation;
  rotation.col(0) = Eigen::Vector3d(0, 1, 0);
  rotation.col(2) = Eigen::Vector3d(0, 0, 1);
  rotation.col(1) = rotation.col(2).cross(rotation.col(0));
  rotation = Eigen::AngleAxisd(-10.0 * M_PI / 180.0, Eigen::Vector3d::UnitY()) * rotation;
  laser.camera_from_laser = Rigid3d(Eigen::Quaterniond(rotation), Eigen::Vector3d(0.3, 0.0, 0.02));
  laser.p1 = p1;
  return laser;
}

// Points on the sheet at several ranges and along the line.
std::vector<Eigen::Vector3d> SheetPoints(const LineProjector& laser) {
  std::vector<Eigen::Vector3d> points;
  for (double z = 0.5; z <= 5.0; z += 0.75) {
    for (double x = -0.4; x <= 0.4; x += 0.1) {
      const Eigen::Vector3d in_laser(x * z, laser.p1 * x * x * z, z);  // y/z = p1 (x/z)^2
      points.push_back(laser.camera_from_laser * in_laser);
    }
  }
  return points;
}

// A sheet point projects to a pixel whose ray triangulates back to it.
TEST(LineProjector, TriangulationRoundTripsThroughTheCamera) {
  const Camera camera = Camera::Flat3();
  for (double p1 : {0.0, 0.02, -0.05}) {
    const LineProjector laser = TestLaser(p1);
    int checked = 0;
    for (const auto& point : SheetPoints(laser)) {
      ASSERT_NEAR(*laser.SheetResidual(point), 0.0, 1e-12);
      const auto pixel = camera.Project(point, ProjectionMethod::kExact);
      if (!pixel || !camera.InImage(*pixel)) continue;
      const auto ray = camera.BackProject(*pixel);
      ASSERT_TRUE(ray.has_value());
      const auto triangulated = laser.Triangulate(*ray);
      ASSERT_TRUE(triangulated.has_value()) << point.transpose();
      EXPECT_LT((*triangulated - point).norm(), 1e-9) << "p1 " << p1 << " " << point.transpose();
      ++checked;
    }
    EXPECT_GT(checked, 20) << p1;
  }
}

// For p1 = 0 the result is eq. 5.2: the ray-plane intersection.
TEST(LineProjector, PlanarSheetMatchesEquation52) {
  const LineProjector laser = TestLaser(0.0);
  const Camera camera = Camera::Flat1();
  const auto ray = camera.BackProject(Eigen::Vector2d(900.0, 300.0));
  const Eigen::Vector3d sheet_normal = laser.camera_from_laser.rotation * Eigen::Vector3d::UnitY();
  const Eigen::Vector3d p0 = laser.camera_from_laser.translation;
  const Eigen::Vector3d expected =
      ray->direction * ((p0 - ray->origin).dot(sheet_normal) / ray->direction.dot(sheet_normal)) +
      ray->origin;
  EXPECT_LT((*laser.Triangulate(*ray) - expected).norm(), 1e-12);
}

TEST(LineProjector, MissesAreReported) {
  const LineProjector laser = TestLaser(0.0);
  // A ray parallel to the sheet, and one pointing away from it.
  const Eigen::Vector3d in_sheet = laser.camera_from_laser.rotation * Eigen::Vector3d(0.3, 0, 1);
  EXPECT_FALSE(laser.Triangulate(Ray{Eigen::Vector3d::Zero(), in_sheet.normalized()}).has_value());
  const Ray away{Eigen::Vector3d::Zero(), Eigen::Vector3d(-1, 0, 0.01).normalized()};
  EXPECT_FALSE(laser.Triangulate(away).has_value());
  EXPECT_FALSE(TestLaser(0.03).Triangulate(away).has_value());
}

struct SheetCost {
  explicit SheetCost(const Eigen::Vector3d& point) : point_(point) {}
  template <typename T>
  bool operator()(const T* q, const T* t, const T* p1, T* residual) const {
    const T point[3] = {T(point_.x()), T(point_.y()), T(point_.z())};
    return LineProjectorModel::SheetResidual(q, t, p1[0], point, residual);
  }
  Eigen::Vector3d point_;
};

struct TriangulationCost {
  template <typename T>
  bool operator()(const T* q, const T* t, const T* p1, const T* origin, const T* direction,
                  T* residual) const {
    return LineProjectorModel::Triangulate(q, t, p1[0], origin, direction, residual);
  }
};

TEST(LineProjector, JacobiansMatchNumericDifferentiation) {
  const LineProjector laser = TestLaser(0.03);
  const Eigen::Quaterniond& r = laser.camera_from_laser.rotation;
  const double q[4] = {r.w(), r.x(), r.y(), r.z()};
  const double* t = laser.camera_from_laser.translation.data();
  const double p1[1] = {0.03};
  ceres::AutoDiffCostFunction<SheetCost, 1, 4, 3, 1> sheet(
      new SheetCost(Eigen::Vector3d(0.1, 0.2, 2.0)));
  std::vector<const double*> sheet_parameters = {q, t, p1};
  EXPECT_EQ(CheckJacobians(sheet, sheet_parameters, 1e-7), "");
  // The ray through the image of a sheet point at 2 m.
  const Camera camera = Camera::Flat1();
  const Eigen::Vector3d on_sheet =
      laser.camera_from_laser * Eigen::Vector3d(0.2, 0.03 * 0.01 * 2.0, 2.0);
  const auto ray = camera.BackProject(*camera.Project(on_sheet));
  ASSERT_TRUE(laser.Triangulate(*ray).has_value());
  ceres::AutoDiffCostFunction<TriangulationCost, 3, 4, 3, 1, 3, 3> triangulation(
      new TriangulationCost);
  std::vector<const double*> tri_parameters = {q, t, p1, ray->origin.data(), ray->direction.data()};
  EXPECT_EQ(CheckJacobians(triangulation, tri_parameters, 1e-6), "");
}

}  // namespace
}  // namespace uwscan
