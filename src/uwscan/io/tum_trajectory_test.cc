#include "uwscan/io/tum_trajectory.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "uwscan/io/tum.h"
#include "uwscan/util/error.h"

namespace uwscan {
namespace {

TEST(TumTrajectory, RoundTripsPosesAndGaps) {
  TumTrajectory trajectory;
  trajectory.poses.push_back({1.5, Rigid3d(Eigen::Quaterniond(0.5, 0.5, -0.5, 0.5),
                                           Eigen::Vector3d(1e-3, -2.25, 1.0 / 3))});
  trajectory.poses.push_back({1.6, Rigid3d()});
  trajectory.gaps.emplace_back(2.0, 2.5, "too few map points tracked (3)");
  const std::string text = TumTrajectoryToText(trajectory);
  const TumTrajectory back = ParseTumTrajectory(text, "test");
  ASSERT_EQ(back.poses.size(), 2u);
  ASSERT_EQ(back.gaps.size(), 1u);
  EXPECT_EQ(back.gaps[0].reason, "too few map points tracked (3)");
  EXPECT_DOUBLE_EQ(back.gaps[0].end_s, 2.5);
  EXPECT_DOUBLE_EQ(back.poses[0].timestamp_s, 1.5);
  EXPECT_EQ(back.poses[0].world_from_camera.translation,
            trajectory.poses[0].world_from_camera.translation);
  EXPECT_EQ(back.poses[0].world_from_camera.rotation.coeffs(),
            trajectory.poses[0].world_from_camera.rotation.coeffs());
  EXPECT_EQ(TumTrajectoryToText(back), text);
}

// A file saved by a Windows editor starts with a UTF-8 byte order mark; its
// first line was "expected 8 numbers".
TEST(TumTrajectory, AByteOrderMarkIsSkipped) {
  for (const char* first : {"# t x y z qx qy qz qw\n", ""}) {
    const std::string text = std::string("\xEF\xBB\xBF") + first + "1 0 0 0 0 0 0 1\n";
    const TumTrajectory trajectory = ParseTumTrajectory(text, "bom.tum");
    ASSERT_EQ(trajectory.poses.size(), 1u);
    EXPECT_DOUBLE_EQ(trajectory.poses[0].timestamp_s, 1.0);
  }
}

TEST(TumTrajectory, ErrorsNameTheLine) {
  try {
    ParseTumTrajectory("# c\n0 1 2 3 0 0 0 1\n1 2 3\n", "gt.tum");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("gt.tum:3"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ParseTumTrajectory("0 1 2 3 0 0 0 2\n", "x"), Error);    // not unit
  EXPECT_THROW(ParseTumTrajectory("0 1 2 3 0 0 0 1 9\n", "x"), Error);  // extra field
  EXPECT_THROW(ReadTumTrajectory("/nonexistent/gt.tum"), Error);
  // A CSV trajectory (EuRoC's): the line and the separator are named.
  try {
    ParseTumTrajectory(
        "#timestamp,p_x,p_y,p_z,q_w,q_x,q_y,q_z\n1403636579758555392,4.6,-1.8,0.8,"
        "0.53,-0.15,-0.83,-0.08\n",
        "euroc.csv");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("euroc.csv:2: commas: a TUM trajectory's fields", 0), 0u)
        << e.what();
  }
}

// Out of order (two rows swapped, a repeated time): refused by both
// readers, with the line, rather than interpolated between wrong neighbours.
// A TUM file written in nanoseconds (an INS log, a bag's export): its
// poses 20 ms apart read as 2e7 s apart, and a scan 0.2 s long fell
// between two of them, every frame placed with the first pose. Refused.
TEST(TumTrajectory, TimestampsInNanosecondsAreRefused) {
  try {
    ParseTumTrajectory("0 0 0 0 0 0 0 1\n20000000 0 0 0 0 0 0 1\n40000000 0 0 0 0 0 0 1\n",
                       "ins.tum");
    FAIL();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(),
                 "ins.tum: timestamps step by 2e+07 s from one to the next (median): they are in "
                 "seconds, and these look like nanoseconds (divide by 1e9); more than 600 s apart "
                 "they are no scan");
  }
  EXPECT_NO_THROW(
      ParseTumTrajectory("1700000000.00 0 0 0 0 0 0 1\n1700000000.02 0 0 0 0 0 0 1\n", "x"));
}

TEST(TumTrajectory, TimestampsMustIncrease) {
  const std::string swapped = "# t x y z qx qy qz qw\n0.5 0 0 0 0 0 0 1\n0.25 0 0 0 0 0 0 1\n";
  try {
    ParseTumTrajectory(swapped, "ins.tum");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("ins.tum:3: timestamps must increase (0.25 after 0.5)"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(ParseTumTrajectory("1 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n", "x"), Error);
  const auto path = std::filesystem::temp_directory_path() /
                    ("uwscan_tum_order_" + std::to_string(::getpid()) + ".tum");
  std::ofstream(path) << swapped;
  try {
    ReadTum(path);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(":3: timestamps must increase"), std::string::npos)
        << e.what();
  }
  std::filesystem::remove(path);
}

// The pose nearest a time, within a tolerance; the earlier of two as near.
TEST(Tum, NearestInTime) {
  std::vector<StampedPose> poses;
  for (int i = 0; i < 5; ++i) poses.push_back({0.1 * i, Rigid3d({1, 0, 0, 0}, {double(i), 0, 0})});
  const auto nearest = [&](double t, double max_dt) {
    const StampedPose* pose = NearestInTime(poses, t, max_dt);
    return pose ? pose->world_from_camera.translation.x() : -1.0;
  };
  EXPECT_EQ(nearest(0.21, 0.05), 2.0);
  EXPECT_EQ(nearest(0.29, 0.05), 3.0);
  EXPECT_EQ(nearest(0.25, 0.06), 2.0);  // as near as 3: the earlier
  EXPECT_EQ(nearest(-0.02, 0.05), 0.0);
  EXPECT_EQ(nearest(0.43, 0.05), 4.0);
  EXPECT_EQ(nearest(0.25, 0.04), -1.0);  // none within
  EXPECT_EQ(nearest(0.6, 0.05), -1.0);
  EXPECT_EQ(NearestInTime({}, 0.0, 1.0), nullptr);
}

}  // namespace
}  // namespace uwscan
