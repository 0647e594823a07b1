#include "uwscan/laser/motion_filter.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "uwscan/util/error.h"

namespace uwscan::laser {
namespace {

// A camera 2 m above a flat floor moving along its x axis: the laser line
// stays at the same column (flat floor), a painted stripe across the track
// moves through the image with the floor.
class MotionFilterTest : public ::testing::Test {
 protected:
  static constexpr double kHeight = 2.0;
  static constexpr double kLaserColumn = 400.0;

  Camera camera_ = Camera::Flat1();
  // world_from_camera of frame k: camera looking down at the floor z = 0
  // (camera z = world -z), moved by `step` along x per frame.
  Rigid3d Pose(int k, double step) const {
    Eigen::Matrix3d r;
    r << 1, 0, 0, 0, -1, 0, 0, 0, -1;
    return Rigid3d(Eigen::Quaterniond(r), Eigen::Vector3d(step * k, 0, kHeight));
  }
  // The floor point seen at a pixel from pose `pose`.
  Eigen::Vector3d OnFloor(const Eigen::Vector2d& pixel) const {
    const auto ray = camera_.BackProject(pixel);
    const double s = (kHeight - ray->origin.z()) / ray->direction.z();
    return ray->At(s);
  }
  // Candidates of frame k: the laser's column and the stripe at world x =
  // stripe_x, on every 4th row; the profile: the laser points.
  // The stripe may be painted on a box top `stripe_height` above the floor.
  void Frame(int k, double step, double stripe_x, std::vector<LaserPoint>* candidates,
             Profile* profile, std::vector<double>* stripe_columns,
             double stripe_height = 0.0) const {
    const Rigid3d camera_from_world = Pose(k, step).Inverse();
    candidates->clear();
    profile->points.clear();
    stripe_columns->clear();
    for (int row = 20; row < camera_.height - 20; row += 4) {
      LaserPoint laser;
      laser.u = kLaserColumn;
      laser.v = row;
      candidates->push_back(laser);
      ProfilePoint point;
      point.pixel = {laser.u, laser.v};
      point.point_in_camera = OnFloor(point.pixel);
      profile->points.push_back(point);
      // The stripe's point on this row: world (stripe_x, y, 0) with y such
      // that it lands on the row (solve along the stripe numerically).
      const Eigen::Vector3d on_row = Pose(k, step) * OnFloor({kLaserColumn, double(row)});
      const auto pixel =
          camera_.Project(camera_from_world * Eigen::Vector3d(stripe_x, on_row.y(), stripe_height));
      if (!pixel || !camera_.InImage(*pixel)) continue;
      LaserPoint stripe;
      stripe.u = pixel->x();
      stripe.v = pixel->y();
      candidates->push_back(stripe);
      stripe_columns->push_back(stripe.u);
    }
  }
};

TEST_F(MotionFilterTest, AStripeMovingWithTheFloorIsExcludedTheLineIsNot) {
  MotionFilter filter(camera_, MotionFilterOptions{});
  std::vector<LaserPoint> candidates;
  Profile profile;
  std::vector<double> stripe;
  const double step = 0.03;  // 3 cm per frame: ~16 px at 2 m
  for (int k = 0; k < 6; ++k) {
    filter.Begin(k, 0.1 * k);
    Frame(k, step, 0.4, &candidates, &profile, &stripe);
    if (k < 2) {
      // No two poses yet: nothing to predict from.
      EXPECT_FALSE(filter.Predicate()) << k;
    } else {
      ASSERT_TRUE(filter.Predicate()) << k;
      EXPECT_GE(filter.references(), 1);
      const auto excluded = filter.Predicate();
      int stripe_excluded = 0, laser_excluded = 0;
      for (const LaserPoint& c : candidates) {
        const bool is_laser = c.u == kLaserColumn;
        (is_laser ? laser_excluded : stripe_excluded) +=
            excluded(c.u, static_cast<int>(std::lround(c.v)));
      }
      EXPECT_EQ(laser_excluded, 0) << k;
      EXPECT_GT(stripe_excluded, 0.9 * stripe.size()) << k;
    }
    filter.End(candidates, profile);
    filter.SetPose(k, Pose(k, step));
  }
}

// A marking on a box top 0.5 m above the floor, beside a line that lies on
// the floor: the profile's depth would move it 25 % too little; matched
// along its epipolar curve with an earlier frame and triangulated, it is
// moved to where it is (thesis §5.5). Without the epipolar match it stays.
TEST_F(MotionFilterTest, ARaisedMarkingIsMatchedAlongItsEpipolarCurve) {
  for (const bool epipolar : {false, true}) {
    MotionFilterOptions options;
    options.epipolar = epipolar;
    MotionFilter filter(camera_, options);
    std::vector<LaserPoint> candidates;
    Profile profile;
    std::vector<double> stripe;
    const double step = 0.03;
    int stripe_excluded = 0, stripe_total = 0, laser_excluded = 0;
    for (int k = 0; k < 8; ++k) {
      filter.Begin(k, 0.1 * k);
      Frame(k, step, 0.45, &candidates, &profile, &stripe, /*stripe_height=*/0.5);
      if (k >= 3) {
        const auto excluded = filter.Predicate();
        ASSERT_TRUE(excluded) << k;
        EXPECT_EQ(filter.epipolar_matches() > 0, epipolar) << k;
        for (const LaserPoint& c : candidates) {
          const bool hit = excluded(c.u, static_cast<int>(std::lround(c.v)));
          if (c.u == kLaserColumn) {
            laser_excluded += hit;
          } else {
            stripe_excluded += hit;
            ++stripe_total;
          }
        }
      }
      filter.End(candidates, profile);
      filter.SetPose(k, Pose(k, step));
    }
    ASSERT_GT(stripe_total, 100);
    EXPECT_EQ(laser_excluded, 0) << epipolar;
    if (epipolar) {
      EXPECT_GT(stripe_excluded, 0.9 * stripe_total);
    } else {
      EXPECT_LT(stripe_excluded, 0.1 * stripe_total);
    }
  }
}

// Hovering: the floor does not move across the line, line and stripe move
// alike (the thesis's critical motion); nothing is compared, nothing
// excluded.
TEST_F(MotionFilterTest, WithoutMotionNothingCanBeToldApart) {
  MotionFilter filter(camera_, MotionFilterOptions{});
  std::vector<LaserPoint> candidates;
  Profile profile;
  std::vector<double> stripe;
  for (int k = 0; k < 5; ++k) {
    filter.Begin(k, 0.1 * k);
    Frame(k, 0.0, 0.4, &candidates, &profile, &stripe);  // hovering: critical motion
    EXPECT_FALSE(filter.Predicate()) << k;
    EXPECT_EQ(filter.references(), 0);
    filter.End(candidates, profile);
    filter.SetPose(k, Pose(k, 0.0));
  }
}

TEST_F(MotionFilterTest, TheLineMovingAgainstTheSceneIsKept) {
  // The laser's line moving across the image by itself (a servo, or the
  // floor's depth changing) while the scene moves the other way: kept.
  MotionFilter filter(camera_, MotionFilterOptions{});
  std::vector<LaserPoint> candidates;
  Profile profile;
  std::vector<double> stripe;
  const double step = 0.03;
  for (int k = 0; k < 5; ++k) {
    filter.Begin(k, 0.1 * k);
    Frame(k, step, 0.4, &candidates, &profile, &stripe);
    for (LaserPoint& c : candidates) {
      if (c.u == kLaserColumn) c.u += 20.0 * k;  // +20 px per frame
    }
    for (ProfilePoint& p : profile.points) p.pixel.x() += 20.0 * k;
    if (k >= 2) {
      const auto excluded = filter.Predicate();
      ASSERT_TRUE(excluded);
      for (const LaserPoint& c : candidates) {
        if (std::abs(c.u - (kLaserColumn + 20.0 * k)) < 1e-9) {
          EXPECT_FALSE(excluded(c.u, static_cast<int>(std::lround(c.v)))) << k << " " << c.v;
        }
      }
    }
    filter.End(candidates, profile);
    filter.SetPose(k, Pose(k, step));
  }
}

TEST(MotionFilterOptionsTest, BadOptionsAreRejected) {
  MotionFilterOptions options;
  options.tolerance_of_shift = 0.6;  // would exclude the line itself
  EXPECT_THROW(MotionFilter(Camera::Flat1(), options), Error);
  options = {};
  options.near_factor = 0.0;  // would search the curve up to the camera
  EXPECT_THROW(MotionFilter(Camera::Flat1(), options), Error);
}

}  // namespace
}  // namespace uwscan::laser
