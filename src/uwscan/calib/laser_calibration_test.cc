#include "uwscan/calib/laser_calibration.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "uwscan/calib/board_pose.h"
#include "uwscan/calib/synthetic_views.h"
#include "uwscan/util/error.h"

namespace uwscan {
namespace {

// Thesis §6.2 laser-tilt set-up: a flat-port camera (Flat1) and a line laser
// 0.3 m to its right behind its own flat port, tilted by `tilt_deg` about
// the laser's line axis, which bends the sheet (Fig. 6.4).
struct TiltedLaser {
  Rigid3d camera_from_laser;
  double tilt_deg = 0.0;

  explicit TiltedLaser(double tilt) : tilt_deg(tilt) {
    const double a = 12.0 * M_PI / 180.0;  // toe-in towards the optical axis
    Eigen::Matrix3d r;
    r.col(0) = Eigen::Vector3d(0, 1, 0);                       // line along camera y
    r.col(2) = Eigen::Vector3d(-std::sin(a), 0, std::cos(a));  // projection direction
    r.col(1) = r.col(2).cross(r.col(0));
    camera_from_laser = Rigid3d(Eigen::Quaterniond(r), Eigen::Vector3d(0.3, 0.0, 0.0));
  }
  // Water ray of the fan ray (s, 0, 1), camera frame: the laser as an
  // inverse camera behind a port (d_air 5 mm, 10 mm glass, n 1.77 / 1.337).
  bool Ray(double s, Eigen::Vector3d* origin, Eigen::Vector3d* direction) const {
    const double tilt = tilt_deg * M_PI / 180.0;
    const double normal[3] = {0.0, std::sin(tilt), std::cos(tilt)};
    const double port[5] = {0.005, 0.010, 1.0, 1.77, 1.337};
    const double ray[3] = {s, 0.0, 1.0};
    double o[3], d[3];
    if (!FlatPortModel::RefractRay(normal, port, ray, o, d)) return false;
    *origin = camera_from_laser * Eigen::Vector3d(o[0], o[1], o[2]);
    *direction = camera_from_laser.rotation * Eigen::Vector3d(d[0], d[1], d[2]);
    return true;
  }
};

const BoardSpec kBoard{6, 9, 0.08};

// A board across the sheet's central ray at camera depth `range`, turned
// by +-0.25 rad about y (alternating with k) and 0.15 rad about x.
Rigid3d BoardAcrossSheet(const TiltedLaser& laser, double range, int k) {
  Eigen::Vector3d o = Eigen::Vector3d::Zero(), d = Eigen::Vector3d::UnitZ();
  EXPECT_TRUE(laser.Ray(0.0, &o, &d));
  const Eigen::Vector3d hit = o + (range - o.z()) / d.z() * d;
  const Eigen::Quaterniond rotation(
      Eigen::AngleAxisd(0.25 * (k % 2 ? 1 : -1), Eigen::Vector3d::UnitY()) *
      Eigen::AngleAxisd(0.15, Eigen::Vector3d::UnitX()));
  const Eigen::Vector3d centre((kBoard.cols - 1) * kBoard.square_m / 2,
                               (kBoard.rows - 1) * kBoard.square_m / 2, 0.0);
  return Rigid3d(rotation, hit - rotation * centre);
}

// Laser views of the given boards: board poses estimated from noisy
// corners, laser pixels (where the sheet crosses the board) with noise.
std::vector<LaserView> MakeViews(const Camera& camera, const TiltedLaser& laser,
                                 const std::vector<Rigid3d>& boards, double noise_px,
                                 unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_px);
  std::vector<LaserView> views;
  Eigen::Vector3d o = Eigen::Vector3d::Zero(), d = Eigen::Vector3d::UnitZ();
  for (size_t k = 0; k < boards.size(); ++k) {
    const Rigid3d& truth_pose = boards[k];
    std::vector<Eigen::Vector2d> corners;
    EXPECT_TRUE(ProjectBoard(camera, kBoard, truth_pose, 5.0, &corners)) << k;
    for (auto& c : corners) c += Eigen::Vector2d(noise(rng), noise(rng));
    const auto pose = EstimateBoardPose(camera, kBoard, corners);
    if (!pose) {
      ADD_FAILURE() << "no board pose for board " << k;
      continue;
    }
    LaserView view;
    view.name = "board";
    view.name += std::to_string(k);
    view.camera_from_board = pose->camera_from_board;
    const Eigen::Vector3d normal = truth_pose.rotation * Eigen::Vector3d::UnitZ();
    for (double s = -0.6; s <= 0.6; s += 0.004) {
      if (!laser.Ray(s, &o, &d)) continue;
      const double l = normal.dot(truth_pose.translation - o) / normal.dot(d);
      const Eigen::Vector3d on_board = truth_pose.Inverse() * (o + l * d);
      if (on_board.y() < 0 || on_board.y() > (kBoard.rows - 1) * kBoard.square_m ||
          on_board.x() < 0 || on_board.x() > (kBoard.cols - 1) * kBoard.square_m) {
        continue;
      }
      const auto pixel = camera.Project(o + l * d);
      if (!pixel || !camera.InImage(*pixel)) continue;
      view.laser_pixels.push_back(*pixel + Eigen::Vector2d(noise(rng), noise(rng)));
    }
    views.push_back(view);
  }
  return views;
}

std::vector<LaserView> MakeViews(const Camera& camera, const TiltedLaser& laser,
                                 const std::vector<double>& ranges, double noise_px,
                                 unsigned seed) {
  std::vector<Rigid3d> boards;
  for (size_t k = 0; k < ranges.size(); ++k)
    boards.push_back(BoardAcrossSheet(laser, ranges[k], k));
  return MakeViews(camera, laser, boards, noise_px, seed);
}

// Reference projector for a tilt: the model fitted to exact sheet points
// over 0.5-2 m (as the thesis's simulated reference, §6.2 Results).
LaserCalibrationResult ReferenceFit(const TiltedLaser& laser) {
  std::vector<Eigen::Vector3d> points;
  for (double s = -0.5; s <= 0.5; s += 0.02) {
    Eigen::Vector3d o = Eigen::Vector3d::Zero(), d = Eigen::Vector3d::UnitZ();
    if (!laser.Ray(s, &o, &d)) continue;
    for (double range = 0.5; range <= 2.0; range += 0.1) points.push_back(o + range * d);
  }
  LaserCalibrationOptions options;
  options.ransac_threshold_m = 0.05;
  options.nominal_camera_from_laser = laser.camera_from_laser;
  return FitLaserProjector(points, options);
}

double AngleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::min(1.0, std::abs(a.normalized().dot(b.normalized())))) * 180 / M_PI;
}

TEST(LaserCalibration, OrthogonalPortRecoversPlaneAndBaseline) {
  const Camera camera = Camera::Flat1();
  const TiltedLaser laser(0.0);
  const Eigen::Vector3d true_normal = laser.camera_from_laser.RotationMatrix().col(1);
  const double true_baseline = std::abs(true_normal.dot(laser.camera_from_laser.translation));
  LaserCalibrationOptions options;
  options.nominal_camera_from_laser = laser.camera_from_laser;
  for (double noise : {0.0, 0.1}) {
    const auto views = MakeViews(camera, laser, {1.0, 1.4, 1.8}, noise, 3);
    const LaserCalibrationResult result = CalibrateLaser(camera, views, options);
    const Eigen::Vector3d normal = result.laser.camera_from_laser.RotationMatrix().col(1);
    std::printf(
        "noise %.1f px: normal error %.4f deg, baseline %.3f mm (truth %.3f), p1 %.2e, "
        "plane rms %.3f mm, sheet rms %.3f mm, %d/%d inliers\n",
        noise, AngleDeg(normal, true_normal), result.baseline_m * 1e3, true_baseline * 1e3,
        result.laser.p1, result.plane_rms_m * 1e3, result.sheet_rms_m * 1e3, result.inliers,
        result.points);
    EXPECT_LT(AngleDeg(normal, true_normal), noise > 0 ? 0.05 : 1e-6);
    EXPECT_NEAR(result.baseline_m, true_baseline, noise > 0 ? 5e-4 : 1e-8);
    EXPECT_NEAR(result.laser.p1, 0.0, noise > 0 ? 2e-3 : 1e-8);
    EXPECT_EQ(result.inliers, result.points);
  }
}

TEST(LaserCalibration, BendFollowsLaserPortTilt) {
  const Camera camera = Camera::Flat1();
  std::printf("tilt_deg  p1_reference  p1_calibrated  baseline_mm  model_rms_mm\n");
  double previous_p1 = 0.0;
  for (double tilt : {0.0, 2.0, 4.0, 6.0, 8.0, 10.0}) {
    const TiltedLaser laser(tilt);
    const LaserCalibrationResult reference = ReferenceFit(laser);
    LaserCalibrationOptions options;
    options.nominal_camera_from_laser = laser.camera_from_laser;
    options.ransac_threshold_m = 0.005;
    const LaserCalibrationResult result =
        CalibrateLaser(camera, MakeViews(camera, laser, {1.0, 1.4, 1.8}, 0.1, 5), options);
    std::printf("%8.1f  %12.5f  %13.5f  %11.3f  %12.4f\n", tilt, reference.laser.p1,
                result.laser.p1, result.baseline_m * 1e3, reference.sheet_rms_m * 1e3);
    // p1 grows monotonically with the tilt and calibration reproduces it.
    if (tilt > 0) {
      EXPECT_GT(std::abs(reference.laser.p1), std::abs(previous_p1));
    }
    EXPECT_NEAR(result.laser.p1, reference.laser.p1, 0.1 * std::abs(reference.laser.p1) + 2e-3);
    previous_p1 = reference.laser.p1;
  }
}

TEST(LaserCalibration, ServoSweepOverFixedBoard) {
  const Camera camera = Camera::Flat1();
  const TiltedLaser laser0(0.0);
  // Servo axis along the laser line through the laser centre (§6.5).
  ServoAxis axis{laser0.camera_from_laser.translation,
                 laser0.camera_from_laser.RotationMatrix().col(0)};
  // One board fixed at ~1.2 m, slanted; the sweep moves the line across it.
  const Rigid3d board = BoardAcrossSheet(laser0, 1.2, 1);
  std::vector<LaserView> views;
  for (double angle_deg = -6.0; angle_deg <= 6.0; angle_deg += 3.0) {
    TiltedLaser laser = laser0;
    const Eigen::AngleAxisd turn(angle_deg * M_PI / 180.0, axis.direction);
    laser.camera_from_laser =
        Rigid3d(turn * laser0.camera_from_laser.rotation, laser0.camera_from_laser.translation);
    auto view = MakeViews(camera, laser, std::vector<Rigid3d>{board}, 0.1,
                          7 + static_cast<int>(angle_deg + 10))[0];
    view.servo_angle_rad = angle_deg * M_PI / 180.0;
    views.push_back(view);
  }
  LaserCalibrationOptions options;
  options.nominal_camera_from_laser = laser0.camera_from_laser;
  const LaserCalibrationResult result = CalibrateLaser(camera, views, options, &axis);
  const Eigen::Vector3d true_normal = laser0.camera_from_laser.RotationMatrix().col(1);
  const Eigen::Vector3d normal = result.laser.camera_from_laser.RotationMatrix().col(1);
  std::printf("servo: normal error %.4f deg, baseline %.3f mm, plane rms %.3f mm\n",
              AngleDeg(normal, true_normal), result.baseline_m * 1e3, result.plane_rms_m * 1e3);
  EXPECT_LT(AngleDeg(normal, true_normal), 0.05);
  EXPECT_NEAR(result.baseline_m, std::abs(true_normal.dot(laser0.camera_from_laser.translation)),
              5e-4);
}

TEST(LaserCalibration, OneDistanceIsAnError) {
  const Camera camera = Camera::Flat1();
  const TiltedLaser laser(0.0);
  const auto views = MakeViews(camera, laser, std::vector<double>{1.0}, 0.1, 3);
  EXPECT_THROW(CalibrateLaser(camera, views, LaserCalibrationOptions()), Error);
}

}  // namespace
}  // namespace uwscan
