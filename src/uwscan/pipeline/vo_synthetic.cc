#include "uwscan/pipeline/vo_synthetic.h"

#include <chrono>
#include <cmath>
#include <opencv2/imgcodecs.hpp>

#include "uwscan/io/rig_yaml.h"
#include "uwscan/io/tum_trajectory.h"
#include "uwscan/pipeline/vo_dataset.h"
#include "uwscan/util/atomic_file.h"
#include "uwscan/util/error.h"
#include "uwscan/util/interrupt.h"
#include "uwscan/util/stopwatch.h"
#include "uwscan/vo/testing/plane_renderer.h"

namespace uwscan {

void SyntheticVoOptions::Check() const {
  if (scenario != "transect" && scenario != "hover") {
    throw UsageError("scenario must be transect or hover, not '" + scenario + "'");
  }
  if (frames < 2) throw UsageError("--frames must be >= 2");
  if (width < 64 || width > 4096 || width % 4 != 0) {
    throw UsageError("--width must be a multiple of 4 in 64..4096");
  }
  UWS_USAGE_CHECK(length_m > 0 && length_m <= 10000, "--length must be in (0, 10000] m, got ",
                  length_m);
  UWS_USAGE_CHECK(altitude_m > 0.3 && altitude_m <= 100, "--altitude must be in (0.3, 100] m, got ",
                  altitude_m);
  UWS_USAGE_CHECK(d_air_m >= 0 && d_air_m <= 0.1, "--d-air must be in [0, 0.1] m, got ", d_air_m);
  UWS_USAGE_CHECK(frame_rate_hz > 0 && frame_rate_hz <= 10000,
                  "--rate must be in (0, 10000] Hz, got ", frame_rate_hz);
  if (medium != "clear" && medium != "medium") {
    throw UsageError("--medium must be clear or medium, not '" + medium + "'");
  }
}

SyntheticVoSummary WriteSyntheticVoDataset(const std::filesystem::path& out_dir,
                                           const SyntheticVoOptions& options) {
  options.Check();
  InterruptibleScope interruptible;
  const auto start = std::chrono::steady_clock::now();
  StagedFolder staged(out_dir);  // nothing under its name until the whole dataset is written
  const std::filesystem::path& dir = staged.path();
  std::filesystem::create_directories(dir / "frames");
  Camera base = Camera::Flat1();
  base.port.d_air = options.d_air_m;
  Camera camera = vo::testing::ScaledCamera(base, options.width / 1280.0);

  // Poses.
  std::vector<Rigid3d> poses;
  if (options.scenario == "transect") {
    poses = vo::testing::TransectPoses(options.frames, options.length_m, options.altitude_m);
  } else {
    // Approach over 0.5 m in 40 frames, then hover with millimetre
    // micro-motion (sub-millimetre to 3 mm, tenths of a degree).
    const int approach = std::min(40, options.frames / 2);
    const auto approach_poses =
        vo::testing::TransectPoses(approach + 1, 0.5, options.altitude_m, 0.0, 0.0);
    const Rigid3d& hover = approach_poses.back();
    for (int i = 0; i < approach; ++i) poses.push_back(approach_poses[size_t(i)]);
    for (int i = approach; i < options.frames; ++i) {
      const double t = (i - approach) / options.frame_rate_hz;
      const Eigen::Vector3d offset(0.003 * std::sin(2.1 * t), 0.002 * std::sin(1.3 * t + 1),
                                   0.001 * std::sin(3.7 * t));
      const Eigen::Quaterniond wobble(
          Eigen::AngleAxisd(0.004 * std::sin(1.7 * t), Eigen::Vector3d::UnitX()) *
          Eigen::AngleAxisd(0.003 * std::sin(2.3 * t + 2), Eigen::Vector3d::UnitY()));
      poses.push_back(Rigid3d(hover.rotation * wobble, hover.translation + offset));
    }
  }
  // Terrain covering the footprint along the path.
  vo::testing::TerrainOptions terrain_options;
  double x_min = 1e9, x_max = -1e9;
  for (const Rigid3d& pose : poses) {
    x_min = std::min(x_min, pose.translation.x());
    x_max = std::max(x_max, pose.translation.x());
  }
  const double footprint = 1.5 * options.altitude_m;
  terrain_options.x_min_m = x_min - footprint;
  terrain_options.x_max_m = x_max + footprint;
  terrain_options.y_min_m = -footprint - 0.3;
  terrain_options.y_max_m = footprint + 0.3;
  terrain_options.seed = options.seed;
  const vo::testing::TexturedTerrain terrain(terrain_options);
  const vo::testing::PlaneRenderer renderer(camera, terrain);

  vo::testing::RenderOptions render;
  if (options.medium == "clear") {
    render.noise_sigma = 1.0;
  } else {
    render.contrast = 0.45;
    render.backscatter = 70.0;
    render.noise_sigma = 2.5;
  }
  Rig rig;
  if (options.laser) {
    // A laser 0.3 m to the right whose sheet (containing the camera's y
    // direction) meets the floor at x = 0.1 m at the nominal altitude; the
    // renderer draws the line at that column.
    const Eigen::Vector3d x_laser(0, 1, 0);
    const Eigen::Vector3d z_laser = Eigen::Vector3d(-0.2, 0, options.altitude_m).normalized();
    Eigen::Matrix3d r;
    r.col(0) = x_laser;
    r.col(1) = z_laser.cross(x_laser);
    r.col(2) = z_laser;
    LineProjector projector;
    projector.camera_from_laser = Rigid3d(Eigen::Quaterniond(r), Eigen::Vector3d(0.3, 0, 0));
    rig.lasers.push_back(projector);
    render.laser_column_px = camera.Project(Eigen::Vector3d(0.1, 0, options.altitude_m))->x();
    render.laser_slope = 0.0;
    render.laser_width_px = 1.5 * options.width / 640.0;
  }
  rig.cameras.push_back(camera);
  WriteRigYaml(dir / "rig.yaml", rig);

  FramesCsvWriter frames(dir / "frames.csv", /*with_laser_angle=*/false);
  TumTrajectory truth;
  for (int i = 0; i < options.frames; ++i) {
    ThrowIfInterrupted();
    render.noise_seed = options.seed * 100003u + unsigned(i);
    const cv::Mat image = renderer.Render(poses[size_t(i)], render);
    char name[64];
    std::snprintf(name, sizeof(name), "frames/%06d.png", i);
    UWS_CHECK(cv::imwrite((dir / name).string(), image), (dir / name).string(), ": cannot write");
    const double t = i / options.frame_rate_hz;
    frames.Add({i, t, name, std::nullopt, std::nullopt});
    truth.poses.push_back({t, poses[size_t(i)]});
  }
  frames.Commit();
  WriteTumTrajectory(dir / "groundtruth.tum", truth);
  staged.Commit();
  SyntheticVoSummary summary;
  summary.frames = options.frames;
  for (size_t i = 1; i < poses.size(); ++i) {
    summary.path_length_m += (poses[i].translation - poses[i - 1].translation).norm();
  }
  summary.seconds = SecondsSince(start);
  return summary;
}

}  // namespace uwscan
