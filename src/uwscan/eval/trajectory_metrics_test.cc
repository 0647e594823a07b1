#include "uwscan/eval/trajectory_metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "uwscan/util/error.h"

namespace uwscan {
namespace {

TEST(AlignSim3, RecoversAKnownSimilarity) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-5, 5);
  Sim3d truth;
  truth.scale = 2.5;
  truth.rotation =
      Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, -1).normalized()));
  truth.translation = Eigen::Vector3d(1, -2, 3);
  std::vector<Eigen::Vector3d> source, target;
  for (int i = 0; i < 20; ++i) {
    source.emplace_back(u(rng), u(rng), u(rng));
    target.push_back(truth * source.back());
  }
  const auto sim = AlignSim3(source, target);
  ASSERT_TRUE(sim.has_value());
  EXPECT_NEAR(sim->scale, 2.5, 1e-12);
  EXPECT_LT(sim->rotation.angularDistance(truth.rotation), 1e-12);
  EXPECT_LT((sim->translation - truth.translation).norm(), 1e-11);
  // Without scale the rotation is still found.
  const auto se3 = AlignSim3(source, target, false);
  ASSERT_TRUE(se3.has_value());
  EXPECT_EQ(se3->scale, 1.0);
  EXPECT_LT(se3->rotation.angularDistance(truth.rotation), 1e-9);
  // Collinear points do not fix the rotation.
  std::vector<Eigen::Vector3d> line = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
  EXPECT_FALSE(AlignSim3(line, line).has_value());
  EXPECT_FALSE(AlignSim3({{0, 0, 0}}, {{0, 0, 0}}).has_value());
}

// Ground truth: the unit square at z = 0, identity rotations, t = 0..3 s.
// Estimate: the same with heights +a, -a, +a, -a. The offsets have zero
// mean and no correlation with the square, so the SE(3) alignment is the
// identity and every metric is known by hand.
std::vector<StampedPose> Square(double a) {
  const Eigen::Vector3d corners[4] = {{0, 0, a}, {1, 0, -a}, {1, 1, a}, {0, 1, -a}};
  std::vector<StampedPose> poses;
  for (int i = 0; i < 4; ++i) poses.push_back({double(i), Rigid3d({1, 0, 0, 0}, corners[i])});
  return poses;
}

TEST(TrajectoryMetrics, HandComputedSquare) {
  TrajectoryMetricsOptions options;
  options.align_scale = false;
  options.drift_lengths_m = {1.0};
  const TrajectoryMetrics m = ComputeTrajectoryMetrics(Square(0.1), Square(0.0), options);
  EXPECT_EQ(m.associated, 4);
  EXPECT_NEAR(m.path_length_m, 3.0, 1e-12);
  EXPECT_NEAR(m.ate_rmse_m, 0.1, 1e-12);
  EXPECT_NEAR(m.ate_max_m, 0.1, 1e-12);
  // Consecutive relative motions are off by 2a = 0.2 m, rotations exact.
  EXPECT_EQ(m.rpe_pairs, 3);
  EXPECT_NEAR(m.rpe_trans_rmse_m, 0.2, 1e-12);
  EXPECT_NEAR(m.rpe_rot_rmse_deg, 0.0, 1e-9);
  // Three 1 m segments, each 0.2 m off: 20 %.
  EXPECT_EQ(m.drift_segments, 3);
  EXPECT_NEAR(m.drift_trans_percent, 20.0, 1e-9);
  EXPECT_NEAR(m.drift_rot_deg_per_m, 0.0, 1e-9);
}

TEST(TrajectoryMetrics, Sim3AlignmentShrinksTheNoisyEstimate) {
  // With scale, Umeyama shrinks the estimate by s = 0.5 / (0.5 + a^2) (the
  // offsets add variance, eq. 42) and ATE^2 = 0.5 (s - 1)^2 + s^2 a^2.
  const double a = 0.1, s = 0.5 / (0.5 + a * a);
  std::vector<StampedPose> estimate = Square(a);
  // Any similarity applied to the estimate changes nothing.
  Sim3d sim;
  sim.scale = 3.0;
  sim.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(1.0, Eigen::Vector3d::UnitY()));
  sim.translation = Eigen::Vector3d(5, 6, 7);
  for (auto& pose : estimate) pose.world_from_camera = sim * pose.world_from_camera;
  const TrajectoryMetrics m = ComputeTrajectoryMetrics(estimate, Square(0.0));
  EXPECT_NEAR(m.alignment.scale * 3.0, s, 1e-12);
  EXPECT_NEAR(m.ate_rmse_m, std::sqrt(0.5 * (s - 1) * (s - 1) + s * s * a * a), 1e-12);
}

TEST(TrajectoryMetrics, PerfectEstimateAndGaps) {
  std::vector<StampedPose> truth;
  for (int i = 0; i < 50; ++i) {
    truth.push_back(
        {0.1 * i, Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(0.05 * i, Eigen::Vector3d::UnitZ())),
                          Eigen::Vector3d(0.1 * i, std::sin(0.2 * i), 0.01 * i))});
  }
  std::vector<StampedPose> estimate;
  for (int i = 0; i < 50; ++i) {
    if (i >= 20 && i < 25) continue;  // a gap
    estimate.push_back({0.1 * i + 1e-4, truth[size_t(i)].world_from_camera});
  }
  const TrajectoryMetrics m = ComputeTrajectoryMetrics(estimate, truth);
  EXPECT_EQ(m.associated, 45);
  EXPECT_EQ(m.rpe_pairs, 43);  // no pair across the gap
  EXPECT_LT(m.ate_rmse_m, 1e-9);
  EXPECT_LT(m.drift_trans_percent, 1e-6);
  EXPECT_GT(m.drift_segments, 0);
  // No association at all is an error.
  std::vector<StampedPose> late = estimate;
  for (auto& pose : late) pose.timestamp_s += 100;
  EXPECT_THROW(ComputeTrajectoryMetrics(late, truth), Error);
}

// An estimate of every 5th frame (a 28.8 Hz camera against 144 Hz ground
// truth) has no pair of poses one ground-truth frame apart: by default the
// RPE is taken over the estimate's own step, and says which.
TEST(TrajectoryMetrics, RpeOverTheEstimatesOwnStep) {
  std::vector<StampedPose> truth, estimate;
  for (int i = 0; i < 100; ++i) {
    const Eigen::Vector3d position(0.001 * i, 0.0, 0.01 * std::sin(0.1 * i));
    truth.push_back({i / 144.0, Rigid3d({1, 0, 0, 0}, position)});
    // Every 5th, each 1 mm off along y, alternately: 2 mm between steps.
    const Eigen::Vector3d off(0.0, i % 10 ? 0.001 : -0.001, 0.0);
    if (i % 5 == 0) estimate.push_back({i / 144.0, Rigid3d({1, 0, 0, 0}, position + off)});
  }
  TrajectoryMetricsOptions options;
  options.align_scale = false;
  const TrajectoryMetrics own = ComputeTrajectoryMetrics(estimate, truth, options);
  EXPECT_EQ(own.rpe_step, 5);
  EXPECT_EQ(own.rpe_pairs, 19);
  EXPECT_NEAR(own.rpe_trans_rmse_m, 0.002, 1e-9);
  EXPECT_NE(FormatTrajectoryMetrics(own).find("RPE per 5 frames: 2.000 mm"), std::string::npos)
      << FormatTrajectoryMetrics(own);
  EXPECT_EQ(own.ToJson()["rpe"]["step"], 5);
  // A step asked for is kept: one frame apart, no pair.
  options.rpe_step = 1;
  const TrajectoryMetrics asked = ComputeTrajectoryMetrics(estimate, truth, options);
  EXPECT_EQ(asked.rpe_step, 1);
  EXPECT_EQ(asked.rpe_pairs, 0);
  // An estimate of every frame, with a gap: one frame.
  std::vector<StampedPose> gapped = truth;
  gapped.erase(gapped.begin() + 40, gapped.begin() + 60);
  EXPECT_EQ(ComputeTrajectoryMetrics(gapped, truth).rpe_step, 1);
}

// The same 2 mm of smooth position error pins the scale of a 20 m transect
// down to a fraction of a per cent, and that of a hover spanning 3 cm only to
// several per cent: the block-bootstrap interval says so, and holds the
// truth in both.
TEST(TrajectoryMetrics, ScaleIntervalShowsHowWellTheScaleIsPinned) {
  const auto run = [](double extent_m) {
    std::vector<StampedPose> truth, estimate;
    for (int i = 0; i < 600; ++i) {
      const double t = i / 100.0;
      const Eigen::Vector3d p(extent_m * t / 6.0, 0.3 * extent_m * std::sin(t),
                              0.2 * extent_m * std::cos(0.7 * t));
      const Eigen::Vector3d error(0.002 * std::sin(3.1 * t), 0.002 * std::cos(2.3 * t),
                                  0.002 * std::sin(1.7 * t + 1.0));
      truth.push_back({t, Rigid3d({1, 0, 0, 0}, p)});
      estimate.push_back({t, Rigid3d({1, 0, 0, 0}, 0.5 * (p + error))});  // monocular: half
    }
    return ComputeTrajectoryMetrics(estimate, truth);
  };
  const TrajectoryMetrics transect = run(20.0), hover = run(0.03);
  for (const auto& m : {transect, hover}) {
    EXPECT_LE(m.scale_interval_low, m.alignment.scale);
    EXPECT_GE(m.scale_interval_high, m.alignment.scale);
    EXPECT_LT(m.scale_interval_low, 2.0 + 1e-3);
    EXPECT_GT(m.scale_interval_high, 2.0 - 1e-3);
  }
  const double transect_width = transect.scale_interval_high - transect.scale_interval_low;
  const double hover_width = hover.scale_interval_high - hover.scale_interval_low;
  EXPECT_LT(transect_width, 0.002);
  EXPECT_GT(hover_width, 0.05);
}

// The motion ratios need no alignment: a trajectory whose translations are
// 2 % too long and whose rotations are right, expressed in another world
// frame, gives 1.02 and 1.00; rotations 1 % short give 0.99.
TEST(TrajectoryMetrics, MotionRatiosSeparateTranslationFromRotation) {
  std::vector<StampedPose> truth, estimate;
  const Rigid3d other_world(
      Eigen::Quaterniond(Eigen::AngleAxisd(0.8, Eigen::Vector3d(0.3, -1, 0.5).normalized())),
      Eigen::Vector3d(4, -2, 1));
  for (int i = 0; i < 400; ++i) {
    const double t = i / 144.0;
    const Eigen::Vector3d p(0.02 * std::sin(2.0 * t), 0.015 * std::cos(3.1 * t), 0.01 * t);
    const Eigen::Vector3d w(0.01 * std::sin(1.3 * t), 0.008 * std::cos(2.2 * t), 0.005 * t);
    const auto rotation = [](const Eigen::Vector3d& v) {
      return Eigen::Quaterniond(Eigen::AngleAxisd(v.norm(), v.normalized()));
    };
    truth.push_back({t, Rigid3d(rotation(w), p)});
    estimate.push_back({t, other_world * Rigid3d(rotation(0.99 * w), 1.02 * p)});
  }
  const TrajectoryMetrics m = ComputeTrajectoryMetrics(estimate, truth);
  EXPECT_EQ(m.motion_lag, 40);
  EXPECT_NEAR(m.motion_translation_ratio, 1.02, 1e-9);
  EXPECT_NEAR(m.motion_rotation_ratio, 0.99, 2e-3);
  EXPECT_NE(FormatTrajectoryMetrics(m).find("translation 1.0200, rotation 0.99"), std::string::npos)
      << FormatTrajectoryMetrics(m);
}

// A hover whose estimate turns, now and then, about the point 2 m ahead
// (the bas-relief error of a narrow field over a flat scene): the camera's
// motion comes out too long or short, what it looks at moves exactly as in
// the truth, and the translation error is all of that kind. A plain scale
// error is none of it.
TEST(TrajectoryMetrics, ViewedMotionSeparatesATurnAboutTheSceneFromAScaleError) {
  const double depth = 2.0;
  const Eigen::Vector3d viewed(0, 0, depth);
  const auto rotation = [](const Eigen::Vector3d& v) {
    return v.norm() > 0 ? Eigen::Quaterniond(Eigen::AngleAxisd(v.norm(), v.normalized()))
                        : Eigen::Quaterniond::Identity();
  };
  std::vector<StampedPose> truth, turned, scaled;
  for (int i = 0; i < 300; ++i) {
    const double t = i / 144.0;
    const Eigen::Vector3d p(0.02 * std::sin(5.0 * t), 0.015 * std::cos(4.1 * t),
                            0.005 * std::sin(3.0 * t));
    const Eigen::Vector3d w(0.008 * std::sin(4.3 * t), 0.01 * std::cos(3.2 * t),
                            0.004 * std::sin(t));
    const Rigid3d pose(rotation(w), p);
    truth.push_back({t, pose});
    // Turned about `viewed` (camera frame) by up to 1.5 mrad.
    const Eigen::Quaterniond turn =
        rotation(Eigen::Vector3d(0.0015 * std::sin(2.3 * t), 0.001 * std::cos(1.7 * t), 0));
    turned.push_back({t, pose * Rigid3d(turn, viewed - turn * viewed)});
    scaled.push_back({t, Rigid3d(pose.rotation, 1.02 * p)});
  }
  TrajectoryMetricsOptions options;
  options.motion_lag = 30;
  options.viewed_depth_m = depth;
  const TrajectoryMetrics t = ComputeTrajectoryMetrics(turned, truth, options);
  EXPECT_GT(std::abs(t.motion_translation_ratio - 1.0), 0.01);
  EXPECT_NEAR(t.viewed_motion_ratio, 1.0, 1e-9);
  EXPECT_GT(t.turn_about_scene_share, 0.99);
  EXPECT_NE(FormatTrajectoryMetrics(t).find("the point 2.000 m ahead"), std::string::npos)
      << FormatTrajectoryMetrics(t);
  const TrajectoryMetrics s = ComputeTrajectoryMetrics(scaled, truth, options);
  EXPECT_NEAR(s.motion_translation_ratio, 1.02, 1e-9);
  EXPECT_LT(s.turn_about_scene_share, 0.01);
  EXPECT_GT(s.viewed_motion_ratio, 1.0);  // the camera's part of the viewed point's motion
  const nlohmann::json json = t.ToJson();
  EXPECT_EQ(json["motion"]["lag_frames"], 30);
  EXPECT_DOUBLE_EQ(json["motion"]["translation_ratio"].get<double>(), t.motion_translation_ratio);
  EXPECT_DOUBLE_EQ(json["motion"]["viewed_point_ratio"].get<double>(), t.viewed_motion_ratio);
  EXPECT_DOUBLE_EQ(json["motion"]["turn_about_scene_share"].get<double>(),
                   t.turn_about_scene_share);
  EXPECT_DOUBLE_EQ(json["sim3"]["scale"].get<double>(), t.alignment.scale);
  EXPECT_DOUBLE_EQ(json["ate_m"]["rmse"].get<double>(), t.ate_rmse_m);
  EXPECT_EQ(json["associated"], 300);
  // Not asked for: not computed, not printed.
  options.viewed_depth_m = 0.0;
  const TrajectoryMetrics plain = ComputeTrajectoryMetrics(turned, truth, options);
  EXPECT_EQ(plain.viewed_depth_m, 0.0);
  EXPECT_EQ(FormatTrajectoryMetrics(plain).find("ahead"), std::string::npos);
  EXPECT_FALSE(plain.ToJson()["motion"].contains("viewed_point_ratio"));
  options.viewed_depth_m = -1.0;
  EXPECT_THROW(ComputeTrajectoryMetrics(turned, truth, options), Error);
}

// A static scan (a laser on a servo, the platform standing still): no
// motion to align by. The estimate is aligned through its first pose and
// the ATE is how far it wandered; the scale, the drift and the motion
// ratios are not measured (null), not shown as 1 or 0. A ground truth that
// moves but cannot be aligned is still an error.
TEST(TrajectoryMetrics, AStillPlatformIsAlignedByItsFirstPose) {
  const Rigid3d standing(Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX())),
                         Eigen::Vector3d(1.0, 2.0, 2.0));
  std::vector<StampedPose> truth, estimate;
  for (int i = 0; i < 40; ++i) {
    truth.push_back({0.01 * i, standing});
    // The estimate in its own world (the first camera's), wandering 1 mm
    // along x by the end.
    const Rigid3d wander(Eigen::Quaterniond::Identity(), Eigen::Vector3d(0.001 * i / 39.0, 0, 0));
    estimate.push_back({0.01 * i, wander});
  }
  const TrajectoryMetrics m = ComputeTrajectoryMetrics(estimate, truth);
  EXPECT_TRUE(m.aligned_by_first_pose);
  EXPECT_EQ(m.associated, 40);
  EXPECT_DOUBLE_EQ(m.alignment.scale, 1.0);
  EXPECT_NEAR(m.ate_max_m, 0.001, 1e-12);  // the last pose, 1 mm from the first
  EXPECT_NEAR(m.ate_mean_m, 0.0005, 1e-12);
  EXPECT_EQ(m.drift_segments, 0);
  EXPECT_FALSE(m.motion_translation_measured || m.motion_rotation_measured);
  const nlohmann::json json = m.ToJson();
  EXPECT_TRUE(json["sim3"]["aligned_by_first_pose"].get<bool>());
  EXPECT_TRUE(json["sim3"]["scale_interval_95"].is_null());
  EXPECT_TRUE(json["drift"]["translation_percent"].is_null());
  EXPECT_TRUE(json["motion"]["translation_ratio"].is_null());
  EXPECT_TRUE(json["motion"]["rotation_ratio"].is_null());
  const std::string text = FormatTrajectoryMetrics(m);
  EXPECT_NE(text.find("the platform stands still, so the estimate is aligned through its first "
                      "pose (no scale)"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("drift (KITTI): no segment"), std::string::npos) << text;
  EXPECT_NE(text.find("translation - (the truth does not move), rotation - (the truth does not "
                      "turn)"),
            std::string::npos)
      << text;
  EXPECT_EQ(text.find("Sim(3) scale"), std::string::npos) << text;

  // A moving truth is aligned by Sim(3) as before.
  std::vector<StampedPose> moving = truth;
  for (size_t i = 0; i < moving.size(); ++i)
    moving[i].world_from_camera.translation += Eigen::Vector3d(0.01 * i, 0.002 * (i % 3), 0);
  const TrajectoryMetrics aligned = ComputeTrajectoryMetrics(moving, moving);
  EXPECT_FALSE(aligned.aligned_by_first_pose);
  EXPECT_TRUE(aligned.ToJson()["sim3"]["scale_interval_95"].is_array());
  // A truth along a line (degenerate for Sim(3)) that moves: still an error.
  std::vector<StampedPose> line = truth;
  for (size_t i = 0; i < line.size(); ++i)
    line[i].world_from_camera.translation += Eigen::Vector3d(0.01 * i, 0, 0);
  EXPECT_THROW(ComputeTrajectoryMetrics(line, line), Error);
}

}  // namespace
}  // namespace uwscan
