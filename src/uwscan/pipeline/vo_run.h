// Controller of `uwscan vo`: streams a dataset through vo::Odometry frame by
// frame, writes the trajectory (TUM, gaps marked) and a per-frame status
// table, and evaluates against groundtruth.tum when there is one.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "uwscan/eval/trajectory_metrics.h"
#include "uwscan/vo/odometry.h"

namespace uwscan {

struct VoJob {
  std::filesystem::path dataset_dir;
  std::filesystem::path trajectory_out;             // TUM
  std::optional<std::filesystem::path> status_out;  // frame,timestamp_s,status,...
  std::string camera_name;                          // default: the first camera
  std::string model = "flatport";                   // flatport | pinhole
  // For --model pinhole on a flat-port rig: the best pinhole + Brown fitted
  // to the port on a plane at this depth (what a user calibrating a pinhole
  // in water would get; eval/port_analysis).
  double pinhole_fit_depth_m = 3.0;
  bool mask_laser = false;
  double mask_margin_px = 6.0;  // dilation of the detector's mask (KLT window support)
  int max_frames = 0;           // 0: all
  int sample_bits = 16;         // ReconstructJob::sample_bits
  // Frames wider than this are tracked at half (quarter, ...) resolution:
  // a raw Bayer frame through the passive colour's own samples (no
  // demosaicking), as the self-referenced scan does. 0: full resolution.
  int max_tracking_width = 640;
  // The tracked image's contrast equalised over a Gaussian of this fraction
  // of its width (fusion::SelfReferencedPoseProvider::NormalizeIllumination;
  // 0 = off). The LED travels with the camera and its fall-off scales the
  // texture's contrast; tracks drift with it. On 20 m simulated transects
  // the odometry then bent the track by a steady 0.15-0.2 deg/m in pitch;
  // equalised, ATE went 32-67 -> 9-19 mm in clear water (BENCHMARKS.md,
  // "Contrast equalised").
  double contrast_sigma_fraction = 0.05;
  bool quiet = false;
  // A 14-keyframe window instead of the library's 7: on 20 m transects in
  // coastal water the drift went from 1.15-1.68 % to 0.73-1.51 % (seven
  // sequences, BENCHMARKS.md "Bundle-adjustment window"), at 1.5x the time.
  // The self-referenced scan keeps 7 (its hover gained nothing).
  vo::OdometryOptions odometry = [] {
    vo::OdometryOptions options;
    options.ba.window_size = 14;
    return options;
  }();
  // odometry.async_bundle_adjustment, which this sets; unset (auto): above
  // vo::kAsyncBundleAdjustmentAboveHz (as `uwscan reconstruct`; 1280x960
  // full VO 133-140 -> 186-189 frames/s of CPU, `uwscan vo bench`).
  std::optional<bool> async_bundle_adjustment;
  void Check() const;
};

// The odometry's command-line options (`--window`, `--ba-time-limit`,
// `--ba-iterations`, `--klt-window`, `--per-cell`, `--max-dormant-frames`,
// `--initial-depth`; `uwscan vo` and `uwscan reconstruct` share some):
// throws UsageError naming the flag.
void CheckOdometryFlags(const vo::OdometryOptions& odometry);
// `--contrast-scale`: in [0, 0.5]; throws UsageError.
void CheckContrastScale(double fraction);

struct VoRunSummary {
  int frames = 0, posed = 0, tracked = 0, lost = 0, invalid = 0, reinitialised = 0;
  int keyframes = 0, gaps = 0, unreadable = 0;
  long tracks_lost_on_mask = 0, tracks_reacquired = 0;  // thesis §5.5 track re-association
  double wall_s = 0.0;
  double vo_s = 0.0;                            // inside Odometry::ProcessFrame
  double tracking_s = 0.0;                      // feature tracking part of it
  double mask_s = 0.0;                          // laser detection for the mask
  double vo_cpu_s = 0.0, tracking_cpu_s = 0.0;  // thread CPU time of the same
  double bundle_adjustment_s = 0.0;             // windowed BA (wall), part of vo_s if not async
  int bundle_adjustments = 0;
  int bundle_adjustments_time_limited = 0;  // stopped by the time limit (load-dependent)
  long rss_kb_at_10_percent = 0, rss_kb_end = 0, peak_rss_kb = 0;
  bool async_bundle_adjustment = false;  // as used (VoJob::async_bundle_adjustment)
  std::string tracked_image;          // what the odometry tracked, e.g. "red samples ..., 640x480"
  std::vector<std::string> warnings;  // first few, for the CLI
  std::optional<TrajectoryMetrics> metrics;
};

VoRunSummary RunVisualOdometry(const VoJob& job);

// Resident set size of this process (kB) from /proc; 0 where unavailable.
long CurrentRssKb();
long PeakRssKb();

}  // namespace uwscan
