// `uwscan vo bench`: speed and memory of the visual odometry on frames
// rendered in memory (no disk), e.g. 10,000 frames circling over a small
// textured sea floor. Reports frames/s of the tracking alone and of the
// whole VO, and the resident memory as the run goes on.
#pragma once

#include <string>
#include <vector>

namespace uwscan {

struct VoBenchmarkOptions {
  int frames = 1000;
  int width = 640;  // height = 3/4 width
  double d_air_m = 0.005;
  double speed_m_per_frame = 0.01;
  double altitude_m = 2.0;
  double loop_radius_m = 1.5;  // circles of this radius, over and over
  int memory_every = 1000;     // sample RSS every this many frames
  bool async_bundle_adjustment = false;
  int klt_window_px = 21;
  bool quiet = false;
  void Check() const;
};

struct VoBenchmarkResult {
  int frames = 0, tracked = 0, lost = 0, reinitialised = 0, keyframes = 0;
  double render_s = 0.0, vo_s = 0.0, tracking_s = 0.0;
  double vo_cpu_s = 0.0, tracking_cpu_s = 0.0;  // thread CPU time
  double max_frame_s = 0.0;                     // slowest ProcessFrame
  std::vector<std::pair<int, long>> rss_kb;     // (frame, RSS)
  int max_map_points = 0, max_keyframes = 0;
};

VoBenchmarkResult RunVoBenchmark(const VoBenchmarkOptions& options);

}  // namespace uwscan
