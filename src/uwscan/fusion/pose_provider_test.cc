#include "uwscan/fusion/pose_provider.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

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

// A trajectory with a gap (uwscan vo's `# gap` comments: tracking lost)
// places no frame inside it; the frames around it get their poses.
TEST(PoseProvider, NoPoseInsideATrajectorysGap) {
  const Rigid3d a(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0, 0, 0));
  const Rigid3d b(Eigen::Quaterniond::Identity(), Eigen::Vector3d(1, 0, 0));
  TrajectoryPoseProvider provider({{0.0, a}, {0.1, a}, {1.0, b}, {1.1, b}}, "vo.tum", 0.05,
                                  {{0.1, 1.0}});
  const auto at = [&](double t) {
    FrameInput frame;
    frame.index = static_cast<int>(std::lround(t * 100));
    frame.timestamp_s = t;
    return provider.Add(frame);
  };
  EXPECT_EQ(at(0.05).size(), 1u);
  EXPECT_TRUE(at(0.5).empty());  // inside the gap: once interpolated between 0.1 and 1.0
  EXPECT_EQ(at(1.0).size(), 1u);
  ASSERT_EQ(at(1.05).size(), 1u);
  EXPECT_EQ(at(1.05).front().world_from_camera.translation.x(), 1.0);
}

// The rms change of the poses two estimates share, in the camera's frame:
// a pose turned about its own centre moves 0 m; a pose moved 3 mm in one
// of two frames moves sqrt(3^2 / 2) mm rms; frames one estimate lacks
// do not count.
TEST(PoseProvider, RmsPoseChangeOverTheSharedPoses) {
  const Rigid3d a(Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY())),
                  Eigen::Vector3d(1, 2, 3));
  const Rigid3d turned(a.rotation * Eigen::AngleAxisd(0.01, Eigen::Vector3d::UnitX()),
                       a.translation);
  const Rigid3d moved(a.rotation, a.translation + a.rotation * Eigen::Vector3d(0, 0.003, 0));
  const auto same = RmsPoseChange({a, a}, {a, a});
  ASSERT_TRUE(same.has_value());
  EXPECT_EQ(same->moved_m, 0.0);
  EXPECT_EQ(same->turned_deg, 0.0);
  const auto change = RmsPoseChange({a, a, a, std::nullopt}, {turned, moved, std::nullopt, a});
  ASSERT_TRUE(change.has_value());
  EXPECT_NEAR(change->moved_m, 0.003 / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(change->turned_deg, 0.01 * 180.0 / M_PI / std::sqrt(2.0), 1e-9);
  EXPECT_FALSE(RmsPoseChange({a, std::nullopt}, {std::nullopt, a}).has_value());
  EXPECT_FALSE(RmsPoseChange({}, {a}).has_value());
}

}  // namespace
}  // namespace uwscan::fusion
