#include "uwscan/vo/odometry.h"

#include <gtest/gtest.h>

#include "uwscan/eval/trajectory_metrics.h"
#include "uwscan/vo/testing/plane_renderer.h"

namespace uwscan::vo {
namespace {

using testing::PlaneRenderer;
using testing::TexturedTerrain;

struct RunOutput {
  std::vector<StampedPose> estimate, truth;
  std::vector<FrameResult> results;
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

}  // namespace
}  // namespace uwscan::vo
