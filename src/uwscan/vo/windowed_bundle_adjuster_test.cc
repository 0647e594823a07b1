#include "uwscan/vo/windowed_bundle_adjuster.h"

#include <gtest/gtest.h>

#include <random>

#include "uwscan/util/jacobian_check.h"
#include "uwscan/vo/cost_functions.h"

namespace uwscan::vo {
namespace {

Camera DeepPortCamera() {
  Camera camera = Camera::Flat3();  // tilted port
  camera.port.d_air = 0.03;
  return camera;
}

TEST(CostFunctions, JacobiansMatchNumericDifferentiation) {
  const Camera camera = DeepPortCamera();
  const CameraParams params(camera);
  const Eigen::Quaterniond q =
      Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, -2, 0.5).normalized()));
  double rotation[4] = {q.x(), q.y(), q.z(), q.w()};
  double translation[3] = {0.1, -0.2, 0.3};
  const Eigen::Vector3d point_camera(0.4, -0.3, 2.0);
  const Eigen::Vector3d world = q.inverse() * (point_camera - Eigen::Vector3d(0.1, -0.2, 0.3));
  double point[3] = {world.x(), world.y(), world.z()};
  const Eigen::Vector2d observed = *camera.Project(point_camera) + Eigen::Vector2d(0.7, -0.4);
  for (ProjectionMethod method :
       {ProjectionMethod::kExact, ProjectionMethod::kTaylor, ProjectionMethod::kPinhole}) {
    std::unique_ptr<ceres::CostFunction> cost(
        ReprojectionCost::Create(params, method, 2, observed, 0.5));
    EXPECT_EQ(CheckJacobians(*cost, {rotation, translation, point}, 1e-6), "") << int(method);
  }
  std::unique_ptr<ceres::CostFunction> range(
      RangeCost::Create(camera.BackProject(observed)->origin, 2.1, 0.002));
  EXPECT_EQ(CheckJacobians(*range, {rotation, translation, point}, 1e-6), "");
  // The exact residual vanishes at the exact projection.
  ReprojectionCost exact(params, ProjectionMethod::kExact, 2, *camera.Project(point_camera), 1.0);
  double residual[2];
  ASSERT_TRUE(exact(rotation, translation, point, residual));
  EXPECT_LT(std::hypot(residual[0], residual[1]), 1e-9);
}

// The chained derivatives (projection differentiated over the camera-frame
// point only) are those of automatic differentiation over all parameters,
// for the point as a parameter and held fixed, for every projection.
TEST(CostFunctions, ChainedDerivativesEqualFullAutomaticDifferentiation) {
  const Camera camera = DeepPortCamera();
  const CameraParams params(camera);
  const Eigen::Quaterniond q =
      Eigen::Quaterniond(Eigen::AngleAxisd(-0.4, Eigen::Vector3d(0.2, 1, -0.7).normalized()));
  const double rotation[4] = {q.x(), q.y(), q.z(), q.w()};
  const double translation[3] = {-0.05, 0.15, 0.2};
  const double point[3] = {0.3, 0.5, 2.4};
  const Eigen::Vector3d in_camera =
      q * Eigen::Vector3d(point[0], point[1], point[2]) + Eigen::Vector3d(translation);
  const Eigen::Vector2d observed = *camera.Project(in_camera) + Eigen::Vector2d(0.6, -0.3);
  for (ProjectionMethod method :
       {ProjectionMethod::kExact, ProjectionMethod::kTaylor, ProjectionMethod::kPinhole}) {
    const ReprojectionCost functor(params, method, 2, observed, 0.7);
    std::unique_ptr<ceres::CostFunction> chained(
        ReprojectionCost::Create(params, method, 2, observed, 0.7));
    ceres::AutoDiffCostFunction<ReprojectionCost, 2, 4, 3, 3> full(new ReprojectionCost(functor));
    std::unique_ptr<ceres::CostFunction> chained_pose(
        PoseReprojectionCost::Create(functor, Eigen::Vector3d(point[0], point[1], point[2])));
    ceres::AutoDiffCostFunction<PoseReprojectionCost, 2, 4, 3> full_pose(
        new PoseReprojectionCost(functor, Eigen::Vector3d(point[0], point[1], point[2])));
    const double* blocks[3] = {rotation, translation, point};
    double r_chained[2], r_full[2], r_pose[2], r_full_pose[2];
    double jc[3][8], jf[3][8], jp[2][8], jfp[2][8];
    double* jc_ptr[3] = {jc[0], jc[1], jc[2]};
    double* jf_ptr[3] = {jf[0], jf[1], jf[2]};
    double* jp_ptr[2] = {jp[0], jp[1]};
    double* jfp_ptr[2] = {jfp[0], jfp[1]};
    ASSERT_TRUE(chained->Evaluate(blocks, r_chained, jc_ptr));
    ASSERT_TRUE(full.Evaluate(blocks, r_full, jf_ptr));
    ASSERT_TRUE(chained_pose->Evaluate(blocks, r_pose, jp_ptr));
    ASSERT_TRUE(full_pose.Evaluate(blocks, r_full_pose, jfp_ptr));
    const int sizes[3] = {8, 6, 6};
    for (int r = 0; r < 2; ++r) {
      EXPECT_NEAR(r_chained[r], r_full[r], 1e-9) << int(method);
      EXPECT_NEAR(r_pose[r], r_full[r], 1e-9) << int(method);
      EXPECT_NEAR(r_full_pose[r], r_full[r], 1e-9) << int(method);
    }
    for (int b = 0; b < 3; ++b) {
      for (int i = 0; i < sizes[b]; ++i) {
        const double tolerance = 1e-9 * (1.0 + std::abs(jf[b][i]));
        EXPECT_NEAR(jc[b][i], jf[b][i], tolerance) << int(method) << " block " << b << " " << i;
        if (b < 2) {
          EXPECT_NEAR(jp[b][i], jf[b][i], tolerance) << int(method) << " block " << b;
          EXPECT_NEAR(jfp[b][i], jf[b][i], tolerance) << int(method) << " block " << b;
        }
      }
    }
    // No Jacobians asked: the residual alone.
    double r_only[2];
    ASSERT_TRUE(chained->Evaluate(blocks, r_only, nullptr));
    EXPECT_NEAR(r_only[0], r_chained[0], 1e-9);
    EXPECT_NEAR(r_only[1], r_chained[1], 1e-9);
  }
}

struct Synthetic {
  SparseMap map;
  std::vector<Rigid3d> truth;  // camera_from_world per keyframe
  std::unordered_map<uint64_t, Eigen::Vector3d> points;
};

// Five keyframes moving along x above a bumpy floor, exact refracted
// observations plus noise.
Synthetic MakeWindow(const Camera& camera, double noise_px, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> x(-1.0, 2.0), y(-0.8, 0.8), z(1.8, 2.4);
  std::normal_distribution<double> noise(0.0, noise_px);
  Synthetic s;
  for (int k = 0; k < 5; ++k) {
    const Eigen::Quaterniond q(
        Eigen::AngleAxisd(0.02 * k, Eigen::Vector3d(0.3, 1, 0).normalized()));
    s.truth.push_back(Rigid3d(q, -(q * Eigen::Vector3d(0.25 * k, 0.02 * k, 0))));
  }
  for (uint64_t id = 1; id <= 300; ++id) s.points[id] = Eigen::Vector3d(x(rng), y(rng), z(rng));
  for (int k = 0; k < 5; ++k) {
    Keyframe kf;
    kf.id = uint64_t(k);
    kf.camera_from_world = s.truth[size_t(k)];
    for (const auto& [id, p] : s.points) {
      const auto pixel = camera.Project(s.truth[size_t(k)] * p);
      if (!pixel || !camera.InImage(*pixel)) continue;
      kf.observations[id] = *pixel + Eigen::Vector2d(noise(rng), noise(rng));
    }
    s.map.keyframes.push_back(kf);
  }
  for (const auto& [id, p] : s.points) s.map.points[id] = {id, p, 0};
  return s;
}

double MaxPoseError(const Synthetic& s) {
  double worst = 0;
  for (size_t k = 0; k < s.truth.size(); ++k) {
    worst = std::max(
        worst, (s.map.keyframes[k].WorldFromCamera().translation - s.truth[k].Inverse().translation)
                   .norm());
  }
  return worst;
}

TEST(WindowedBundleAdjustment, ConvergesFromPerturbedPosesAndPoints) {
  const Camera camera = DeepPortCamera();
  for (ProjectionMethod method : {ProjectionMethod::kExact, ProjectionMethod::kTaylor}) {
    Synthetic s = MakeWindow(camera, 0.0, 5);
    std::mt19937 rng(6);
    std::normal_distribution<double> n(0.0, 1.0);
    for (size_t k = 2; k < 5; ++k) {  // the first two are the gauge
      Keyframe& kf = s.map.keyframes[k];
      kf.camera_from_world.translation += 0.01 * Eigen::Vector3d(n(rng), n(rng), n(rng));
      kf.camera_from_world.rotation =
          kf.camera_from_world.rotation *
          Eigen::Quaterniond(
              Eigen::AngleAxisd(0.01, Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized()));
    }
    for (auto& [id, p] : s.map.points)
      p.position_world += 0.02 * Eigen::Vector3d(n(rng), n(rng), n(rng));
    BundleAdjustmentOptions options;
    options.method = method;
    options.taylor_iterations = 3;
    options.max_iterations = 50;
    options.max_solver_time_s = 10;
    const BundleAdjustmentSummary summary = AdjustWindow(camera, options, &s.map);
    EXPECT_EQ(summary.keyframes, 5);
    EXPECT_GT(summary.initial_rms_px, 5.0);
    EXPECT_LT(summary.final_rms_px, 1e-3) << int(method);
    EXPECT_LT(MaxPoseError(s), 1e-5) << int(method);
    EXPECT_TRUE(summary.removed_observations.empty());
  }
}

TEST(WindowedBundleAdjustment, PinholeResidualIsBiasedOnRefractedData) {
  const Camera camera = DeepPortCamera();
  Synthetic s = MakeWindow(camera, 0.0, 7);
  BundleAdjustmentOptions options;
  options.method = ProjectionMethod::kPinhole;  // ignores the port
  options.outlier_px = 1e6;
  const BundleAdjustmentSummary summary = AdjustWindow(camera, options, &s.map);
  EXPECT_GT(summary.final_rms_px, 0.5);
}

// The window shrunk by 10 % (re-projection errors stay zero, only ranges
// can tell) and ten range constraints in each of the first five keyframes,
// the first `wrong_per_keyframe` of them scaled by `wrong_factor`. Returns
// the number of wrong ones.
int ShrinkAndAddRanges(const Camera& camera, Synthetic* s, double sigma_m,
                       int wrong_per_keyframe = 0, double wrong_factor = 1.0) {
  for (Keyframe& kf : s->map.keyframes) kf.camera_from_world.translation *= 0.9;
  for (auto& [id, p] : s->map.points) p.position_world *= 0.9;
  int wrong = 0;
  for (int k = 0; k < 5; ++k) {
    Keyframe& kf = s->map.keyframes[size_t(k)];
    int added = 0;
    for (const auto& [id, pixel] : kf.observations) {
      const Eigen::Vector3d p = s->truth[size_t(k)] * s->points.at(id);
      const Eigen::Vector3d origin = camera.BackProject(pixel)->origin;
      const bool bad = added < wrong_per_keyframe;
      kf.range_constraints.push_back({id, (p - origin).norm() * (bad ? wrong_factor : 1.0), sigma_m});
      wrong += bad;
      if (++added == 10) break;
    }
  }
  return wrong;
}

// Baseline between keyframes 0 and 4, estimated over true.
double BaselineRatio(const Synthetic& s) {
  const double baseline = (s.map.keyframes[4].WorldFromCamera().translation -
                           s.map.keyframes[0].WorldFromCamera().translation)
                              .norm();
  return baseline / (s.truth[4].Inverse().translation - s.truth[0].Inverse().translation).norm();
}

TEST(WindowedBundleAdjustment, RangeConstraintsFixTheScale) {
  const Camera camera = DeepPortCamera();
  Synthetic s = MakeWindow(camera, 0.0, 8);
  ShrinkAndAddRanges(camera, &s, 0.001);
  BundleAdjustmentOptions options;
  options.max_iterations = 50;
  options.max_solver_time_s = 10;
  const BundleAdjustmentSummary summary = AdjustWindow(camera, options, &s.map);
  EXPECT_EQ(summary.range_residuals, 50);
  EXPECT_NEAR(BaselineRatio(s), 1.0, 1e-3);
}

// Thesis §5.4: where the laser line meets a map point, the keyframe has no
// observation of it (the line masks it) but the range along the ray of the
// pixel it projects to; that ray's origin comes with the constraint. A
// point no keyframe of the window sees gets no range (it would be free
// across its ray).
TEST(WindowedBundleAdjustment, RangesOfPointsUnderTheLineFixTheScale) {
  const Camera camera = DeepPortCamera();
  Synthetic s = MakeWindow(camera, 0.0, 9);
  for (Keyframe& kf : s.map.keyframes) kf.camera_from_world.translation *= 0.9;
  for (auto& [id, p] : s.map.points) p.position_world *= 0.9;
  const uint64_t unseen = 100000;
  s.map.points[unseen] = {unseen, Eigen::Vector3d(0.3, 0.1, 1.8), 0};
  std::unordered_map<uint64_t, int> seen_by;
  for (const Keyframe& kf : s.map.keyframes) {
    for (const auto& [id, pixel] : kf.observations) ++seen_by[id];
  }
  for (int k = 0; k < 5; ++k) {
    Keyframe& kf = s.map.keyframes[size_t(k)];
    std::vector<uint64_t> under_line;
    for (const auto& [id, pixel] : kf.observations) {  // other keyframes still see them
      if (under_line.size() < 10 && id % 5 == uint64_t(k) && seen_by[id] > 1)
        under_line.push_back(id);
    }
    for (uint64_t id : under_line) {
      const Eigen::Vector3d p = s.truth[size_t(k)] * s.points.at(id);
      const auto ray = camera.BackProject(*camera.Project(p));
      ASSERT_TRUE(ray.has_value());
      kf.observations.erase(id);
      RangeConstraint range{id, (p - ray->origin).norm(), 0.001};
      range.ray_origin_camera = ray->origin;
      kf.range_constraints.push_back(range);
    }
    RangeConstraint unseen_range{unseen, 2.0, 0.001};
    unseen_range.ray_origin_camera = Eigen::Vector3d::Zero();
    kf.range_constraints.push_back(unseen_range);
    // Without an origin and without an observation there is no ray.
    kf.range_constraints.push_back({under_line.front(), 2.0, 0.001});
  }
  BundleAdjustmentOptions options;
  options.max_iterations = 50;
  options.max_solver_time_s = 10;
  const BundleAdjustmentSummary summary = AdjustWindow(camera, options, &s.map);
  EXPECT_EQ(summary.range_residuals, 50);
  EXPECT_NEAR(BaselineRatio(s), 1.0, 1e-3);
}

// Thesis §5.4: range constraints under a Cauchy loss, and those still far
// off after the solve removed. Ten of the 50 constraints claim ranges 30 %
// too long (a feature in front of the surface the laser measured): the
// scale must still come out right, and the wrong ones go (all but those
// whose point may slide along its ray to meet them, at most two), no
// right one.
TEST(WindowedBundleAdjustment, WrongRangeConstraintsAreOutvotedAndRemoved) {
  const Camera camera = DeepPortCamera();
  Synthetic s = MakeWindow(camera, 0.0, 8);
  const int wrong = ShrinkAndAddRanges(camera, &s, 0.002, 2, 1.3);
  BundleAdjustmentOptions options;
  options.max_iterations = 50;
  options.max_solver_time_s = 10;
  const BundleAdjustmentSummary summary = AdjustWindow(camera, options, &s.map);
  EXPECT_EQ(summary.range_residuals, 50);
  EXPECT_GE(summary.removed_range_constraints, wrong - 2);
  EXPECT_LE(summary.removed_range_constraints, wrong);
  int left_right = 0;
  for (int k = 0; k < 5; ++k) {
    const Keyframe& kf = s.map.keyframes[size_t(k)];
    for (const RangeConstraint& r : kf.range_constraints) {
      const Eigen::Vector3d p = s.truth[size_t(k)] * s.points.at(r.point_id);
      const Eigen::Vector3d origin = camera.BackProject(kf.observations.at(r.point_id))->origin;
      left_right += std::abs(r.range_m - (p - origin).norm()) < 1e-9;
    }
  }
  EXPECT_EQ(left_right, 50 - wrong);
  EXPECT_NEAR(BaselineRatio(s), 1.0, 2e-3);
}

TEST(WindowedBundleAdjustment, ExtraResidualCallbackSeesTheWindow) {
  const Camera camera = DeepPortCamera();
  Synthetic s = MakeWindow(camera, 0.0, 9);
  BundleAdjustmentOptions options;
  options.window_size = 3;
  size_t keyframes = 0, points = 0;
  options.extra_residuals = [&](ceres::Problem& problem, const WindowParameters& window) {
    keyframes = window.keyframes.size();
    points = window.points.size();
    EXPECT_TRUE(problem.HasParameterBlock(window.keyframes.at(4).rotation));
    EXPECT_EQ(window.keyframes.count(1), 0u);  // outside the window
  };
  options.history_keyframes = 0;
  AdjustWindow(camera, options, &s.map);
  EXPECT_EQ(keyframes, 3u);
  EXPECT_GT(points, 100u);
}

// Keyframes before the window enter with their poses held: the points keep
// the rays of the wider baseline, the held poses do not move, and a held
// observation that stays far off is dropped like any other.
TEST(WindowedBundleAdjustment, HeldKeyframesBeforeTheWindowKeepThePointsRays) {
  const Camera camera = DeepPortCamera();
  auto mean_point_error = [](const Synthetic& s) {
    double sum = 0;
    for (const auto& [id, p] : s.map.points) sum += (p.position_world - s.points.at(id)).norm();
    return sum / double(s.map.points.size());
  };
  BundleAdjustmentOptions options;
  options.window_size = 3;  // keyframes 2-4; 2 and 3 fixed
  options.max_iterations = 50;
  options.max_solver_time_s = 10;
  options.history_keyframes = 0;
  Synthetic alone = MakeWindow(camera, 0.5, 11);
  AdjustWindow(camera, options, &alone.map);
  options.history_keyframes = 2;  // keyframes 0 and 1
  Synthetic held = MakeWindow(camera, 0.5, 11);
  const uint64_t wrong = held.map.keyframes[0].observations.begin()->first;
  held.map.keyframes[0].observations[wrong] += Eigen::Vector2d(25.0, 0.0);
  const Rigid3d kf0 = held.map.keyframes[0].camera_from_world;
  const Rigid3d kf1 = held.map.keyframes[1].camera_from_world;
  AdjustWindow(camera, options, &held.map);
  std::printf("mean point error: window alone %.2f mm, with the held keyframes %.2f mm\n",
              1e3 * mean_point_error(alone), 1e3 * mean_point_error(held));
  EXPECT_LT(mean_point_error(held), 0.7 * mean_point_error(alone));
  EXPECT_EQ(held.map.keyframes[0].camera_from_world.translation, kf0.translation);
  EXPECT_EQ(held.map.keyframes[0].camera_from_world.rotation.coeffs(), kf0.rotation.coeffs());
  EXPECT_EQ(held.map.keyframes[1].camera_from_world.translation, kf1.translation);
  EXPECT_EQ(held.map.keyframes[0].observations.count(wrong), 0u);
  EXPECT_GT(held.map.keyframes[0].observations.size(), 100u);
}

}  // namespace
}  // namespace uwscan::vo
