#include "uwscan/sensor/pinhole.h"

#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>

#include "uwscan/util/jacobian_check.h"

namespace uwscan {
namespace {

const double kIntrinsics[4] = {785.0, 790.0, 641.5, 478.25};
const double kDistortion[5] = {-0.28, 0.09, 0.0012, -0.0008, -0.012};

cv::Mat CameraMatrix() {
  return (cv::Mat_<double>(3, 3) << kIntrinsics[0], 0, kIntrinsics[2], 0, kIntrinsics[1],
          kIntrinsics[3], 0, 0, 1);
}
cv::Mat DistortionCoefficients() {
  return (cv::Mat_<double>(1, 5) << kDistortion[0], kDistortion[1], kDistortion[2], kDistortion[3],
          kDistortion[4]);
}

// Projection agrees with cv::projectPoints to 1e-6 px across the image.
TEST(PinholeModel, ProjectMatchesOpenCv) {
  std::vector<cv::Point3d> points;
  for (double x = -0.75; x <= 0.75; x += 0.05) {
    for (double y = -0.6; y <= 0.6; y += 0.05) points.emplace_back(x * 2.0, y * 2.0, 2.0);
  }
  std::vector<cv::Point2d> expected;
  cv::projectPoints(points, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), CameraMatrix(),
                    DistortionCoefficients(), expected);
  for (size_t i = 0; i < points.size(); ++i) {
    const double point[3] = {points[i].x, points[i].y, points[i].z};
    double pixel[2];
    ASSERT_TRUE(PinholeModel::Project(kIntrinsics, kDistortion, point, pixel));
    EXPECT_NEAR(pixel[0], expected[i].x, 1e-6);
    EXPECT_NEAR(pixel[1], expected[i].y, 1e-6);
  }
}

// Undistortion agrees with cv::undistortPoints (run to convergence) to
// 1e-9 rad over the whole 1280x960 image, and round trips exactly.
TEST(PinholeModel, UndistortMatchesOpenCvOverImage) {
  std::vector<cv::Point2d> pixels;
  for (double u = 0; u <= 1280; u += 32) {
    for (double v = 0; v <= 960; v += 32) pixels.emplace_back(u, v);
  }
  std::vector<cv::Point2d> expected;
  cv::undistortPoints(
      pixels, expected, CameraMatrix(), DistortionCoefficients(), cv::noArray(), cv::noArray(),
      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 1000, 1e-15));
  for (size_t i = 0; i < pixels.size(); ++i) {
    double x, y;
    ASSERT_TRUE(
        PinholeModel::ImageToNormalized(kIntrinsics, kDistortion, pixels[i].x, pixels[i].y, &x, &y))
        << pixels[i];
    // Angle between the two rays.
    const Eigen::Vector3d ours = Eigen::Vector3d(x, y, 1).normalized();
    const Eigen::Vector3d theirs = Eigen::Vector3d(expected[i].x, expected[i].y, 1).normalized();
    EXPECT_LT(std::atan2(ours.cross(theirs).norm(), ours.dot(theirs)), 1e-9) << pixels[i];
    double back[2];
    ASSERT_TRUE(PinholeModel::NormalizedToImage(kIntrinsics, kDistortion, x, y, back));
    EXPECT_NEAR(back[0], pixels[i].x, 1e-9);
    EXPECT_NEAR(back[1], pixels[i].y, 1e-9);
  }
}

TEST(PinholeModel, RejectsPointsBehindAndFoldedPixels) {
  const double behind[3] = {0.1, 0.2, -1.0};
  double pixel[2];
  EXPECT_FALSE(PinholeModel::Project(kIntrinsics, kDistortion, behind, pixel));
  // Strong barrel distortion folds over beyond some radius: no valid inverse.
  const double folded[5] = {-0.6, 0.0, 0.0, 0.0, 0.0};
  double x, y;
  EXPECT_FALSE(PinholeModel::ImageToNormalized(kIntrinsics, folded, 5000.0, 4000.0, &x, &y));
}

// The simulated tank camera's barrel distortion (k1 -0.037, k2 0.0002)
// turns back at r^2 = 9.8905 (72 degrees off the axis) and rises again
// past r^2 = 101. Rays beyond the first fold would land inside the image
// (r = 5 lands at 1.0, r = 12.5 at 1.27, the image's corner near 1.02):
// they are not imaged, and no pixel comes back as one of them.
TEST(PinholeModel, NothingPastTheDistortionsFoldIsImaged) {
  const double tank[5] = {-0.037, 0.0002, 0.0, 0.0, 0.0};
  EXPECT_TRUE(PinholeModel::BeforeRadialFold(tank, 9.85));
  EXPECT_FALSE(PinholeModel::BeforeRadialFold(tank, 9.95));
  EXPECT_FALSE(PinholeModel::BeforeRadialFold(tank, 156.25));  // rising again there
  const double none[5] = {0.0, 0.0, 0.0, 0.0, 0.0};
  EXPECT_TRUE(PinholeModel::BeforeRadialFold(none, 1e12));
  const double barrel[5] = {-0.6, 0.0, 0.0, 0.0, 0.0};  // folds at r^2 = 1 / 1.8
  EXPECT_TRUE(PinholeModel::BeforeRadialFold(barrel, 0.55));
  EXPECT_FALSE(PinholeModel::BeforeRadialFold(barrel, 0.56));
  // k3 alone: the slope 1 - 0.07 s^3 reaches 0 at s = 2.43.
  const double k3[5] = {0.0, 0.0, 0.0, 0.0, -0.01};
  EXPECT_TRUE(PinholeModel::BeforeRadialFold(k3, 2.4));
  EXPECT_FALSE(PinholeModel::BeforeRadialFold(k3, 2.5));
  EXPECT_TRUE(PinholeModel::BeforeRadialFold(kDistortion, 1.04));  // the image's corner

  const double intrinsics[4] = {785.0, 785.0, 640.0, 480.0};
  double pixel[2];
  const double inside[3] = {3.0, 0.0, 1.0};
  ASSERT_TRUE(PinholeModel::Project(intrinsics, tank, inside, pixel));
  double x, y;
  ASSERT_TRUE(PinholeModel::ImageToNormalized(intrinsics, tank, pixel[0], pixel[1], &x, &y));
  EXPECT_NEAR(x, 3.0, 1e-9);
  EXPECT_NEAR(y, 0.0, 1e-9);
  for (double r : {5.0, 12.5}) {
    const double folded[3] = {r * 0.6, r * 0.8, 1.0};
    EXPECT_FALSE(PinholeModel::Project(intrinsics, tank, folded, pixel)) << r;
  }
  // A pixel far out, whose only solution lies on the rising branch.
  EXPECT_FALSE(
      PinholeModel::ImageToNormalized(intrinsics, tank, 640.0 + 785.0 * 24.7, 480.0, &x, &y));
}

// Jacobians through Jets agree with central differences.
struct PinholeProjectionCost {
  explicit PinholeProjectionCost(const double* point) : point_{point[0], point[1], point[2]} {}
  template <typename T>
  bool operator()(const T* intrinsics, const T* distortion, T* residual) const {
    const T point[3] = {T(point_[0]), T(point_[1]), T(point_[2])};
    return PinholeModel::Project(intrinsics, distortion, point, residual);
  }
  double point_[3];
};

struct PinholeUndistortCost {
  PinholeUndistortCost(double u, double v) : u_(u), v_(v) {}
  template <typename T>
  bool operator()(const T* intrinsics, const T* distortion, T* residual) const {
    return PinholeModel::ImageToNormalized(intrinsics, distortion, T(u_), T(v_), &residual[0],
                                           &residual[1]);
  }
  double u_, v_;
};

TEST(PinholeModel, JacobiansMatchNumericDifferentiation) {
  std::vector<const double*> parameters = {kIntrinsics, kDistortion};
  const double point[3] = {0.3, -0.2, 1.5};
  ceres::AutoDiffCostFunction<PinholeProjectionCost, 2, 4, 5> projection(
      new PinholeProjectionCost(point));
  EXPECT_EQ(CheckJacobians(projection, parameters, 1e-7), "");

  ceres::AutoDiffCostFunction<PinholeUndistortCost, 2, 4, 5> undistort(
      new PinholeUndistortCost(1100.0, 120.0));
  EXPECT_EQ(CheckJacobians(undistort, parameters, 1e-7), "");
}

}  // namespace
}  // namespace uwscan
