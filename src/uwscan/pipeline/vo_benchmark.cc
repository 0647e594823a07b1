#include "uwscan/pipeline/vo_benchmark.h"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <iostream>

#include "uwscan/pipeline/vo_run.h"
#include "uwscan/util/error.h"
#include "uwscan/util/stopwatch.h"
#include "uwscan/vo/odometry.h"
#include "uwscan/vo/testing/plane_renderer.h"

namespace uwscan {

void VoBenchmarkOptions::Check() const {
  if (frames < 10) throw UsageError("--frames must be >= 10");
  if (width < 64 || width > 4096 || width % 4 != 0) {
    throw UsageError("--width must be a multiple of 4 in 64..4096");
  }
  if (!(speed_m_per_frame > 0) || !(loop_radius_m > 0) || !(altitude_m > 0.3)) {
    throw UsageError("speed, loop radius and altitude must be positive");
  }
  if (memory_every < 1) throw UsageError("memory sampling interval must be >= 1");
}

VoBenchmarkResult RunVoBenchmark(const VoBenchmarkOptions& options) {
  options.Check();
  Camera base = Camera::Flat1();
  base.port.d_air = options.d_air_m;
  const Camera camera = vo::testing::ScaledCamera(base, options.width / 1280.0);
  vo::testing::TerrainOptions terrain_options;
  const double extent = options.loop_radius_m + 1.5 * options.altitude_m;
  terrain_options.x_min_m = terrain_options.y_min_m = -extent;
  terrain_options.x_max_m = terrain_options.y_max_m = extent;
  const vo::testing::TexturedTerrain terrain(terrain_options);
  const vo::testing::PlaneRenderer renderer(camera, terrain);
  vo::OdometryOptions vo_options;
  vo_options.async_bundle_adjustment = options.async_bundle_adjustment;
  vo_options.tracker.klt_window_px = options.klt_window_px;
  vo::Odometry odometry(camera, vo_options);
  vo::testing::RenderOptions render;
  render.noise_sigma = 1.0;
  VoBenchmarkResult result;
  const bool progress = !options.quiet && isatty(STDERR_FILENO);
  for (int i = 0; i < options.frames; ++i) {
    const double angle = i * options.speed_m_per_frame / options.loop_radius_m;
    const Eigen::Vector3d position(options.loop_radius_m * std::cos(angle),
                                   options.loop_radius_m * std::sin(angle),
                                   options.altitude_m + 0.05 * std::sin(3 * angle));
    const Rigid3d pose =
        vo::testing::DownwardPose(position, angle + M_PI / 2, 0.02 * std::sin(angle));
    render.noise_seed = unsigned(i);
    const auto t0 = std::chrono::steady_clock::now();
    const cv::Mat image = renderer.Render(pose, render);
    result.render_s += SecondsSince(t0);
    const vo::FrameResult r = odometry.ProcessFrame(image, cv::Mat(), i / 144.0);
    result.vo_s += r.total_time_s;
    result.tracking_s += r.tracking_time_s;
    result.vo_cpu_s += r.total_cpu_s;
    result.tracking_cpu_s += r.tracking_cpu_s;
    result.max_frame_s = std::max(result.max_frame_s, r.total_time_s);
    result.tracked += r.status == vo::FrameStatus::kTracked;
    result.lost += r.status == vo::FrameStatus::kLost;
    result.reinitialised += r.status == vo::FrameStatus::kReinitialized;
    result.keyframes += r.keyframe;
    result.max_map_points = std::max(result.max_map_points, int(odometry.map().points.size()));
    result.max_keyframes = std::max(result.max_keyframes, int(odometry.map().keyframes.size()));
    if ((i + 1) % options.memory_every == 0 || i + 1 == options.frames) {
      result.rss_kb.emplace_back(i + 1, CurrentRssKb());
    }
    if (progress && i % 100 == 0) {
      std::cerr << "\rvo bench: frame " << i << "/" << options.frames << std::flush;
    }
  }
  if (progress) std::cerr << "\n";
  result.frames = options.frames;
  return result;
}

}  // namespace uwscan
