#include "uwscan/eval/port_analysis.h"

#include <gtest/gtest.h>

#include <cmath>

namespace uwscan {
namespace {

// The best pinhole for Flat2 at 3 m reproduces thesis Tab. 4.6 (Pin2:
// f = 1046.74 px, principal point unchanged, strong positive k1) and its error
// grows away from the fitting depth (Fig. 4.11 a).
TEST(PortAnalysis, PinholeFitMatchesThesisTable) {
  PinholeFitOptions options;
  options.depth_m = 3.0;
  const PinholeFit fit = FitPinholeToFlatPort(Camera::Flat2(), options);
  EXPECT_NEAR(fit.pinhole.intrinsics[0], 1046.74, 5.0);
  EXPECT_NEAR(fit.pinhole.intrinsics[1], 1046.74, 5.0);
  EXPECT_NEAR(fit.pinhole.intrinsics[2], 640.0, 1e-3);
  EXPECT_NEAR(fit.pinhole.intrinsics[3], 480.0, 1e-3);
  EXPECT_NEAR(fit.pinhole.distortion[0], 0.394, 0.02);
  EXPECT_LT(fit.at_fit.max_px, 0.2);
  const ErrorStats near = PinholeErrorAtDepth(Camera::Flat2(), fit.pinhole, 0.5);
  EXPECT_GT(near.max_px, 10.0 * fit.at_fit.max_px);
}

// A tilted port cannot be absorbed by a pinhole (Fig. 4.12): the principal
// point moves and the residual stays larger than for the orthogonal port.
TEST(PortAnalysis, TiltedPortMovesPrincipalPoint) {
  const PinholeFit flat1 = FitPinholeToFlatPort(Camera::Flat1(), PinholeFitOptions{});
  const PinholeFit flat3 = FitPinholeToFlatPort(Camera::Flat3(), PinholeFitOptions{});
  EXPECT_GT(std::abs(flat3.pinhole.intrinsics[2] - 640.0), 1.0);  // thesis: 644.95
  EXPECT_GT(flat3.at_fit.max_px, flat1.at_fit.max_px);
}

// Eq. 4.27, checked independently: with the optimal air gap, the water ray
// of that angle extended backwards passes through the camera centre.
TEST(PortAnalysis, OptimalAirGapCancelsRefractionForItsRay) {
  for (double degrees : {10.0, 25.0, 40.0}) {
    Camera camera = Camera::Flat1();
    const double angle = degrees * M_PI / 180.0;
    camera.port.d_air = OptimalAirGap(camera.port, angle);
    const double x = std::tan(angle);
    const auto ray = camera.BackProject(Eigen::Vector2d(640.0 + 785.0 * x, 480.0));
    ASSERT_TRUE(ray.has_value());
    const Eigen::Vector3d closest = ray->origin - ray->origin.dot(ray->direction) * ray->direction;
    EXPECT_LT(closest.norm(), 1e-12) << degrees;
  }
}

TEST(PortAnalysis, ErrorStats) {
  const ErrorStats stats = ComputeErrorStats({3.0, 1.0, 2.0, 4.0, 5.0});
  EXPECT_EQ(stats.count, 5);
  EXPECT_DOUBLE_EQ(stats.max_px, 5.0);
  EXPECT_DOUBLE_EQ(stats.median_px, 3.0);
  EXPECT_NEAR(stats.rms_px, std::sqrt(55.0 / 5.0), 1e-12);
}

}  // namespace
}  // namespace uwscan
