#include "uwscan/laser/profile.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace uwscan::laser {
namespace {

// A laser 0.3 m right of the camera, its line vertical in the image.
LineProjector TestLaser(double p1) {
  LineProjector laser;
  Eigen::Matrix3d rotation;
  rotation.col(0) = Eigen::Vector3d(0, 1, 0);
  rotation.col(2) = Eigen::Vector3d(-0.15, 0, 1).normalized();
  rotation.col(1) = rotation.col(2).cross(rotation.col(0));
  laser.camera_from_laser = Rigid3d(Eigen::Quaterniond(rotation), Eigen::Vector3d(0.3, 0, 0));
  laser.p1 = p1;
  return laser;
}

// Points where the (servo-turned) sheet meets a wall at z = 2 m, projected
// exactly, come back from their pixels.
TEST(LaserProfile, TriangulatesDetectionsOnAServo) {
  const Camera camera = Camera::Flat3();
  for (double p1 : {0.0, 0.03}) {
    for (double angle : {-0.1, 0.0, 0.12}) {
      const LineProjector laser = TestLaser(p1);
      const Rigid3d pose = CameraFromLaserAtAngle(laser.camera_from_laser, angle);
      std::vector<LaserPoint> detections;
      std::vector<Eigen::Vector3d> truth;
      for (double x = -0.5; x <= 0.5; x += 0.05) {
        // Ray from the laser origin along (x, p1 x^2, 1), intersected with z = 2.
        const Eigen::Vector3d direction = pose.rotation * Eigen::Vector3d(x, p1 * x * x, 1.0);
        const double lambda = (2.0 - pose.translation.z()) / direction.z();
        const Eigen::Vector3d point = pose.translation + lambda * direction;
        const auto pixel = camera.Project(point);
        if (!pixel || !camera.InImage(*pixel)) continue;
        detections.push_back({pixel->x(), pixel->y(), kGreen, 1.0f, 0});
        truth.push_back(point);
      }
      ASSERT_GT(detections.size(), 10u);
      const Profile profile = TriangulateProfile(camera, laser, pose, detections, 7);
      EXPECT_EQ(profile.frame, 7);
      EXPECT_EQ(profile.failed, 0);
      ASSERT_EQ(profile.points.size(), truth.size());
      for (size_t i = 0; i < truth.size(); ++i) {
        EXPECT_LT((profile.points[i].point_in_camera - truth[i]).norm(), 1e-9);
      }
    }
  }
}

// Walls ever farther along the sheet: the camera ray meets the sheet at an
// ever smaller angle, and a pixel of detection error moves the point by
// ever more of its range. Those past kMaxRangeErrorPerPixel are dropped and
// counted; which, is checked against the range change of the detection
// moved by a pixel across the line, triangulated again.
TEST(LaserProfile, PointsWhoseRayGrazesTheSheetAreDropped) {
  const Camera camera = Camera::Flat3();
  for (double p1 : {0.0, 0.03}) {
    const LineProjector laser = TestLaser(p1);
    std::vector<LaserPoint> detections;
    for (double wall : {1.0, 2.0, 5.0, 10.0, 20.0, 40.0, 80.0, 200.0, 1000.0}) {
      for (double x = -0.1; x <= 0.1; x += 0.1) {
        const Eigen::Vector3d direction =
            laser.camera_from_laser.rotation * Eigen::Vector3d(x, p1 * x * x, 1.0);
        const double lambda = (wall - laser.camera_from_laser.translation.z()) / direction.z();
        const auto pixel = camera.Project(laser.camera_from_laser.translation + lambda * direction);
        ASSERT_TRUE(pixel && camera.InImage(*pixel)) << wall;
        detections.push_back({pixel->x(), pixel->y(), kGreen, 1.0f, 0});
      }
    }
    const Profile all =
        TriangulateProfile(camera, laser, laser.camera_from_laser, detections, 0, 0);
    ASSERT_EQ(all.points.size(), detections.size());
    EXPECT_EQ(all.grazing, 0);
    const Profile gated = TriangulateProfile(camera, laser, laser.camera_from_laser, detections);
    EXPECT_EQ(gated.failed, 0);
    EXPECT_EQ(gated.points.size() + size_t(gated.grazing), detections.size());
    int checked = 0;
    for (const auto& p : all.points) {
      // The line runs down the image: a detection error moves it along u.
      double change = 0.0;
      for (double du : {-1.0, 1.0}) {
        const auto ray = camera.BackProject(p.pixel + Eigen::Vector2d(du, 0.0));
        const auto moved = ray ? laser.Triangulate(*ray) : std::nullopt;
        change = std::max(change,
                          moved ? std::abs(moved->norm() / p.point_in_camera.norm() - 1.0) : 1.0);
      }
      const bool kept = std::any_of(gated.points.begin(), gated.points.end(),
                                    [&](const auto& q) { return q.pixel == p.pixel; });
      // (The limit uses the centre pixel's angle, and a pixel's step is not
      // quite across the sheet: the decision may differ near it.)
      if (change < 0.8 * kMaxRangeErrorPerPixel) {
        EXPECT_TRUE(kept) << p.point_in_camera.z();
      }
      if (change > 1.25 * kMaxRangeErrorPerPixel) {
        EXPECT_FALSE(kept) << p.point_in_camera.z();
      }
      checked += change < 0.8 * kMaxRangeErrorPerPixel || change > 1.25 * kMaxRangeErrorPerPixel;
    }
    EXPECT_GE(checked, 21);
    // This rig (0.3 m between camera and laser, 1280 px wide) measures out
    // to between 10 m (3.2 % per pixel) and 20 m (6.6 %).
    EXPECT_EQ(gated.points.size(), 12u);
    EXPECT_EQ(gated.grazing, 15);
  }
}

TEST(LaserProfile, ServoTurnsAboutTheLineDirection) {
  const LineProjector laser = TestLaser(0.0);
  const Rigid3d turned = CameraFromLaserAtAngle(laser.camera_from_laser, 0.3);
  // The line direction (laser x) and the origin stay; the sheet normal turns by 0.3 rad.
  EXPECT_LT((turned.rotation * Eigen::Vector3d::UnitX() -
             laser.camera_from_laser.rotation * Eigen::Vector3d::UnitX())
                .norm(),
            1e-15);
  EXPECT_EQ(turned.translation, laser.camera_from_laser.translation);
  const double cosine = (turned.rotation * Eigen::Vector3d::UnitY())
                            .dot(laser.camera_from_laser.rotation * Eigen::Vector3d::UnitY());
  EXPECT_NEAR(std::acos(cosine), 0.3, 1e-12);
}

TEST(LaserProfile, MissesAreCountedNotReturned) {
  const Camera camera = Camera::Flat1();
  const LineProjector laser = TestLaser(0.0);
  // A pixel far left: its ray runs away from the laser on the right, and a
  // pixel outside the lens's valid region.
  std::vector<LaserPoint> detections = {{5.0, 480.0, kGreen, 1.0f, 0}};
  const Profile profile = TriangulateProfile(camera, laser, laser.camera_from_laser, detections);
  EXPECT_EQ(profile.points.size() + profile.failed, 1u);
  for (const auto& p : profile.points) EXPECT_TRUE(p.point_in_camera.allFinite());
}

}  // namespace
}  // namespace uwscan::laser
