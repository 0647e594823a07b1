#include "uwscan/fusion/pose_provider.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

namespace uwscan::fusion {
namespace {

TEST(PoseProvider, InterpolatesBetweenPoses) {
  const Rigid3d a(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0, 0, 0));
  const Rigid3d b(Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ())),
                  Eigen::Vector3d(1, 2, 3));
  const std::vector<StampedPose> poses = {{0.0, a}, {1.0, b}};
  const auto mid = InterpolatePose(poses, 0.25, 0.05);
  ASSERT_TRUE(mid.has_value());
  EXPECT_LT((mid->translation - Eigen::Vector3d(0.25, 0.5, 0.75)).norm(), 1e-12);
  EXPECT_NEAR(Eigen::AngleAxisd(mid->rotation).angle(), 0.05, 1e-12);
  EXPECT_FALSE(InterpolatePose(poses, 1.2, 0.05).has_value());
  EXPECT_TRUE(InterpolatePose(poses, 1.04, 0.05).has_value());
  EXPECT_FALSE(InterpolatePose({}, 0.0, 0.05).has_value());
}

}  // namespace
}  // namespace uwscan::fusion
