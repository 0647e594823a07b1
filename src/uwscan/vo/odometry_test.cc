#include "uwscan/vo/odometry.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdlib>

#include "uwscan/eval/port_analysis.h"
#include "uwscan/eval/trajectory_metrics.h"
#include "uwscan/vo/testing/plane_renderer.h"

namespace uwscan::vo {
namespace {

using testing::PlaneRenderer;
using testing::TexturedTerrain;

struct RunOutput {
  std::vector<StampedPose> estimate, truth;
  std::vector<FrameResult> results;
  std::vector<Eigen::Vector3d> map_points;  // world frame of the estimate
};

testing::TerrainOptions SmallTerrain() {
  testing::TerrainOptions terrain;
  terrain.x_min_m = -2.0;
  terrain.x_max_m = 4.5;
  terrain.y_min_m = -2.0;
  terrain.y_max_m = 2.0;
  return terrain;
}

RunOutput RunSequence(const Camera& camera, const Camera& vo_camera, const std::vector<Rigid3d>& poses,
              const TexturedTerrain& terrain, const OdometryOptions& options,
              const testing::RenderOptions& render = {}, bool mask_laser = false,
              int black_frame = -1) {
  PlaneRenderer renderer(camera, terrain);
  Odometry odometry(vo_camera, options);
  const cv::Mat mask = mask_laser ? renderer.LaserMask(render) : cv::Mat();
  RunOutput out;
  for (size_t i = 0; i < poses.size(); ++i) {
    cv::Mat image = renderer.Render(poses[i], render);
    if (int(i) == black_frame) image.setTo(0);
    const double t = 0.1 * double(i);
    FrameResult r = odometry.ProcessFrame(image, mask, t);
    for (const auto& [index, pose] : r.earlier_poses) {
      out.estimate.push_back({0.1 * index, pose});
    }
    if (r.world_from_camera) out.estimate.push_back({t, *r.world_from_camera});
    out.truth.push_back({t, poses[i]});
    out.results.push_back(r);
  }
  for (const auto& [id, point] : odometry.map().points) out.map_points.push_back(point.position_world);
  std::sort(out.estimate.begin(), out.estimate.end(),
            [](const StampedPose& a, const StampedPose& b) { return a.timestamp_s < b.timestamp_s; });
  return out;
}

TEST(Odometry, FlatPortTransectHasLowDrift) {
  const Camera camera = testing::ScaledCamera(Camera::Flat1(), 0.25);
  const TexturedTerrain terrain(SmallTerrain());
  const auto poses = testing::TransectPoses(60, 1.5, 2.0);
  const RunOutput out = RunSequence(camera, camera, poses, terrain, OdometryOptions());
  int tracked = 0;
  for (const auto& r : out.results) {
    tracked += r.status == FrameStatus::kTracked;
    printf("%d %s kf=%d tracks=%d map=%d inl=%d ba=%.2f->%.2f %s\n", r.frame_index,
           FrameStatusName(r.status), r.keyframe, r.tracks, r.map_matches, r.inliers,
           r.bundle_adjustment.initial_rms_px, r.bundle_adjustment.final_rms_px,
           r.message.c_str());
  }
  const TrajectoryMetrics m = ComputeTrajectoryMetrics(out.estimate, out.truth);
  printf("ATE %.4f m drift %.3f %% rpe %.4f\n", m.ate_rmse_m, m.drift_trans_percent,
         m.rpe_trans_rmse_m);
  EXPECT_GE(tracked, 50);
  EXPECT_LT(m.ate_rmse_m, 0.01);
}

TEST(Odometry, PinholeModelBendsTheTrajectory) {
  // A housing with the lens 3 cm behind the port, far from the optimal air
  // gap of eq. 4.27 (Flat1's 5 mm is nearly optimal: its best pinhole is
  // within 0.05 px at 2 m and the models are indistinguishable).
  Camera deep_port = Camera::Flat1();
  deep_port.port.d_air = 0.03;
  const Camera camera = testing::ScaledCamera(deep_port, 0.25);
  PinholeFitOptions fit_options;
  fit_options.depth_m = 1.0;  // calibrated in water on a plane at 1 m, used at 2 m
  fit_options.grid_step_px = 8;
  const Camera pinhole = FitPinholeToFlatPort(camera, fit_options).pinhole;
  testing::TerrainOptions terrain_options = SmallTerrain();
  terrain_options.x_max_m = 8.0;
  const TexturedTerrain terrain(terrain_options);
  const auto poses = testing::TransectPoses(150, 5.0, 2.0);
  const RunOutput flat = RunSequence(camera, camera, poses, terrain, OdometryOptions());
  const RunOutput pin = RunSequence(camera, pinhole, poses, terrain, OdometryOptions());
  const TrajectoryMetrics mf = ComputeTrajectoryMetrics(flat.estimate, flat.truth);
  const TrajectoryMetrics mp = ComputeTrajectoryMetrics(pin.estimate, pin.truth);
  printf("flat port: ATE %.2f mm, drift %.3f %% %.3f deg/m | pinhole: ATE %.2f mm, drift %.3f %% "
         "%.3f deg/m\n",
         1e3 * mf.ate_rmse_m, mf.drift_trans_percent, mf.drift_rot_deg_per_m, 1e3 * mp.ate_rmse_m,
         mp.drift_trans_percent, mp.drift_rot_deg_per_m);
  EXPECT_GE(mf.associated, 145);
  EXPECT_LT(mf.drift_trans_percent, 0.5);
  EXPECT_GT(mp.ate_rmse_m, 3.0 * mf.ate_rmse_m);
  EXPECT_GT(mp.drift_rot_deg_per_m, 3.0 * mf.drift_rot_deg_per_m);
}

TEST(Odometry, LaserMaskIsHonoured) {
  const Camera camera = testing::ScaledCamera(Camera::Flat1(), 0.25);
  const TexturedTerrain terrain(SmallTerrain());
  const auto poses = testing::TransectPoses(30, 0.75, 2.0);
  testing::RenderOptions render;
  render.laser_column_px = 150;
  PlaneRenderer renderer(camera, terrain);
  const cv::Mat mask = renderer.LaserMask(render);
  Odometry odometry(camera, OdometryOptions());
  for (size_t i = 0; i < poses.size(); ++i) {
    odometry.ProcessFrame(renderer.Render(poses[i], render), mask, 0.1 * double(i));
    for (const auto& t : odometry.tracks()) {
      ASSERT_EQ(mask.at<uint8_t>(cvRound(t.pixel.y()), cvRound(t.pixel.x())), 0)
          << "feature " << t.id << " on the laser line in frame " << i;
    }
  }
  const RunOutput out = RunSequence(camera, camera, poses, terrain, OdometryOptions(), render, true);
  const TrajectoryMetrics m = ComputeTrajectoryMetrics(out.estimate, out.truth);
  printf("masked laser ATE %.4f\n", m.ate_rmse_m);
  EXPECT_LT(m.ate_rmse_m, 0.01);
}

TEST(Odometry, RecoversAfterBlackFrame) {
  const Camera camera = testing::ScaledCamera(Camera::Flat1(), 0.25);
  const TexturedTerrain terrain(SmallTerrain());
  const auto poses = testing::TransectPoses(60, 1.5, 2.0);
  const RunOutput out =
      RunSequence(camera, camera, poses, terrain, OdometryOptions(), {}, false, 25);
  bool lost = false, reinitialised = false;
  for (const auto& r : out.results) {
    printf("%d %s %s\n", r.frame_index, FrameStatusName(r.status), r.message.c_str());
    if (r.frame_index == 25) {
      EXPECT_EQ(r.status, FrameStatus::kLost);
      EXPECT_FALSE(r.world_from_camera.has_value());
    }
    lost = lost || r.status == FrameStatus::kLost;
    reinitialised = reinitialised || r.status == FrameStatus::kReinitialized;
  }
  EXPECT_TRUE(lost);
  EXPECT_TRUE(reinitialised);
  EXPECT_EQ(out.results.back().status, FrameStatus::kTracked);
}

}  // namespace
}  // namespace uwscan::vo

namespace uwscan::vo {
TEST(OdometryExperiment, DISABLED_LongPinhole) {
  const double scale = std::getenv("S") ? atof(std::getenv("S")) : 0.25;
  const int frames = std::getenv("N") ? atoi(std::getenv("N")) : 300;
  const double length = std::getenv("L") ? atof(std::getenv("L")) : 10.0;
  const double dair = std::getenv("DAIR") ? atof(std::getenv("DAIR")) : 0.01;
  const double fitd = std::getenv("FITD") ? atof(std::getenv("FITD")) : 1.0;
  Camera base = Camera::Flat1();
  base.port.d_air = dair;
  const Camera camera = testing::ScaledCamera(base, scale);
  PinholeFitOptions fit_options;
  fit_options.depth_m = fitd;
  fit_options.grid_step_px = 8;
  const Camera pinhole = FitPinholeToFlatPort(camera, fit_options).pinhole;
  testing::TerrainOptions t;
  const double tilt = std::getenv("TILT") ? atof(std::getenv("TILT")) : 0.0;
  t.x_max_m = length + 3 + 6 * tilt;
  const testing::TexturedTerrain terrain(t);
  const auto poses = testing::TransectPoses(frames, length, 2.0, 0.1, 0.03, tilt);
  for (int model = 0; model < 2; ++model) {
    const auto start = std::chrono::steady_clock::now();
    PlaneRenderer renderer(camera, terrain);
    OdometryOptions vo_options;
    if (std::getenv("INITD")) vo_options.initial_median_depth_m = atof(std::getenv("INITD"));
    Odometry odometry(model == 0 ? camera : pinhole, vo_options);
    std::vector<StampedPose> est, gt;
    double vo_time = 0;
    int lost = 0;
    for (int i = 0; i < frames; ++i) {
      const cv::Mat image = renderer.Render(poses[size_t(i)]);
      FrameResult r = odometry.ProcessFrame(image, cv::Mat(), 0.1 * i);
      vo_time += r.total_time_s;
      lost += r.status == FrameStatus::kLost;
      if (std::getenv("VERBOSE")) printf("%d %s tr=%d map=%d inl=%d %s\n", i, FrameStatusName(r.status), r.tracks, r.map_matches, r.inliers, r.message.c_str());
      for (const auto& [index, pose] : r.earlier_poses) est.push_back({0.1 * index, pose});
      if (r.world_from_camera) est.push_back({0.1 * i, *r.world_from_camera});
      gt.push_back({0.1 * i, poses[size_t(i)]});
    }
    std::sort(est.begin(), est.end(), [](auto& a, auto& b) { return a.timestamp_s < b.timestamp_s; });
    const TrajectoryMetrics m = ComputeTrajectoryMetrics(est, gt);
    if (std::getenv("PERFRAME")) {
      for (size_t i = 1; i < est.size(); ++i) {
        const Rigid3d a = m.alignment * est[i - 1].world_from_camera, b = m.alignment * est[i].world_from_camera;
        const Rigid3d ga = gt[size_t(std::lround(est[i - 1].timestamp_s * 10))].world_from_camera;
        const Rigid3d gb = gt[size_t(std::lround(est[i].timestamp_s * 10))].world_from_camera;
        const Rigid3d e = (ga.Inverse() * gb).Inverse() * (a.Inverse() * b);
        printf("  %zu err %.2f mm  pos err %.2f mm\n", i, 1000 * e.translation.norm(), 1000 * (b.translation - gb.translation).norm());
      }
    }
    printf("%s: ATE %.4f m, drift %.3f %% %.4f deg/m, RPE %.5f, poses %d lost %d, vo %.1f fps, wall %.1f s\n",
           model == 0 ? "flatport" : "pinhole", m.ate_rmse_m, m.drift_trans_percent,
           m.drift_rot_deg_per_m, m.rpe_trans_rmse_m, m.associated, lost, frames / vo_time,
           std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
}
}  // namespace uwscan::vo
