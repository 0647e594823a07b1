// `uwscan bench pipeline`: the whole self-referenced reconstruction of a
// dataset, timed per stage, with the real-time factor and the peak memory
// of the process (run two lengths to see that it stays flat).
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>

namespace uwscan {

struct PipelineBenchmarkOptions {
  std::filesystem::path dataset;  // empty: simulate tank-target first (not timed)
  int frames = 300;
  int width = 1280;
  int height = 960;
  std::optional<bool> async_bundle_adjustment;  // as reconstruct --async-ba; unset: auto
  int track_every = 0;                          // as reconstruct --track-every (0: auto)
  int start_screen_every = 0;                   // as reconstruct --start-screen-every (0: auto)
  std::optional<int> line_window_px;            // as reconstruct --line-window; unset: its default
  // Read the frame images once before the timed run, so that it times the
  // processing, not the disk (the read is timed apart); false: as they are.
  bool preread = true;
  // Deliver the frames at the camera's pace, as a live camera would, and
  // report how far the cloud falls behind it (ReconstructJob::live): the
  // real-time factor then stays at or below 1 by construction, and the lag
  // tells whether the processing keeps up. One pass, no retry.
  bool live = false;
  std::optional<double> live_max_lag_s;  // as ReconstructJob::live_max_lag_s
  void Check() const;
};

nlohmann::json RunPipelineBenchmark(const PipelineBenchmarkOptions& options);

}  // namespace uwscan
