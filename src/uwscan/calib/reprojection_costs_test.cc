#include "uwscan/calib/reprojection_costs.h"

#include <gtest/gtest.h>

#include <memory>

#include "uwscan/calib/laser_costs.h"
#include "uwscan/util/jacobian_check.h"

namespace uwscan {
namespace {

// A tilted port under water with mild distortion; a corner off-axis.
struct Fixture {
  double intrinsics[4] = {1112.7, 1112.6, 625.6, 443.9};
  double distortion[5] = {-0.0489, 0.1037, 0.0005, -0.0003, 0.01};
  double normal[3] = {0.0698, -0.01, 0.9975};
  double d_air[1] = {0.012};
  double media[4] = {0.006, 1.0, 1.52, 1.333};
  double q[4] = {0.98, 0.1, -0.15, 0.05};
  double t[3] = {-0.05, 0.03, 0.45};
  Eigen::Vector3d point_in_board{0.075, 0.05, 0.0};

  Fixture() {
    const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (double& v : q) v /= norm;
  }
  Eigen::Vector2d ExactPixel() const {
    double point[3], pixel[2] = {0.0, 0.0};
    BoardToCamera(q, t, point_in_board, point);
    const double port[5] = {d_air[0], media[0], media[1], media[2], media[3]};
    EXPECT_TRUE(FlatPortModel::ProjectExact(intrinsics, distortion, normal, port, point, pixel));
    return {pixel[0], pixel[1]};
  }
};

TEST(ReprojectionCosts, FlatPortExactIsZeroAtTruthAndJacobiansMatch) {
  Fixture f;
  const Eigen::Vector2d observed = f.ExactPixel() + Eigen::Vector2d(0.3, -0.2);
  for (auto type : {FlatPortResidualType::kExact, FlatPortResidualType::kTaylor}) {
    std::unique_ptr<ceres::CostFunction> cost(
        FlatPortReprojectionCost::Create(observed, f.point_in_board, type, 2));
    const std::vector<const double*> params = {f.intrinsics, f.distortion, f.normal, f.d_air,
                                               f.media,      f.q,          f.t};
    double residual[2];
    ASSERT_TRUE(cost->Evaluate(params.data(), residual, nullptr));
    // 2 Taylor steps from the measured corner 0.36 px away: within 1e-4 px.
    EXPECT_NEAR(residual[0], -0.3, 1e-4);  // projected - observed
    EXPECT_NEAR(residual[1], 0.2, 1e-4);
    EXPECT_EQ(CheckJacobians(*cost, params, 1e-6), "");
  }
}

TEST(ReprojectionCosts, PinholeJacobiansMatch) {
  Fixture f;
  std::unique_ptr<ceres::CostFunction> cost(
      PinholeReprojectionCost::Create({600.0, 400.0}, f.point_in_board));
  const std::vector<const double*> params = {f.intrinsics, f.distortion, f.q, f.t};
  EXPECT_EQ(CheckJacobians(*cost, params, 1e-7), "");
}

TEST(LaserCosts, SheetJacobiansMatchAndSubspaceManifoldMoves) {
  double q[4] = {0.9, 0.2, -0.3, 0.1};
  const double norm = std::sqrt(0.81 + 0.04 + 0.09 + 0.01);
  for (double& v : q) v /= norm;
  double t[3] = {0.3, 0.01, 0.02};
  double p1[1] = {0.02};
  std::unique_ptr<ceres::CostFunction> cost(LaserSheetCost::Create({0.1, 0.2, 0.8}));
  EXPECT_EQ(CheckJacobians(*cost, {q, t, p1}, 1e-7), "");

  // One direction (0, 0.6, 0.8) and a second one orthogonal to it.
  SubspaceManifold manifold({Eigen::Vector3d(0, 0.6, 0.8), Eigen::Vector3d(1, 0, 0)});
  const double x[3] = {1, 2, 3}, delta[2] = {5, -2};
  double y[3], back[2];
  manifold.Plus(x, delta, y);
  EXPECT_DOUBLE_EQ(y[0], -1.0);
  EXPECT_DOUBLE_EQ(y[1], 5.0);
  EXPECT_DOUBLE_EQ(y[2], 7.0);
  manifold.Minus(y, x, back);
  EXPECT_DOUBLE_EQ(back[0], 5.0);
  EXPECT_DOUBLE_EQ(back[1], -2.0);
  double plus_jacobian[6], minus_jacobian[6];
  manifold.PlusJacobian(x, plus_jacobian);    // 3x2 row-major
  manifold.MinusJacobian(x, minus_jacobian);  // 2x3 row-major
  EXPECT_DOUBLE_EQ(plus_jacobian[1 * 2 + 0], 0.6);
  EXPECT_DOUBLE_EQ(plus_jacobian[0 * 2 + 1], 1.0);
  EXPECT_DOUBLE_EQ(minus_jacobian[0 * 3 + 2], 0.8);
  EXPECT_DOUBLE_EQ(minus_jacobian[1 * 3 + 0], 1.0);
}

}  // namespace
}  // namespace uwscan
