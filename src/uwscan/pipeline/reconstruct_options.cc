// The reconstruction job's checks, and the parsing and resolution of its flags.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <string>
#include <type_traits>
#include <vector>

#include "uwscan/pipeline/reconstruct.h"
#include "uwscan/pipeline/vo_run.h"
#include "uwscan/util/error.h"

namespace uwscan {

void ReconstructJob::Check() const {
  detector.Check();
  CheckSampleBitsOption(sample_bits);
  if (max_frames < 0)
    throw UsageError("--max-frames must be >= 0 (0 = all), got " + std::to_string(max_frames));
  UWS_USAGE_CHECK(!out.empty(), "--out: empty output folder name");
  if (track_every < 0)
    throw UsageError("--track-every must be auto or >= 1, got " + std::to_string(track_every));
  if (line_window_px < 0)
    throw UsageError("--line-window must be >= 0 (0 = whole scan lines), got " +
                     std::to_string(line_window_px));
  if (self_referenced.max_tracking_width < 0)
    throw UsageError("--max-tracking-width must be >= 0 (0 = full resolution), got " +
                     std::to_string(self_referenced.max_tracking_width));
  CheckOdometryFlags(self_referenced.odometry);
  if (contrast_scale) CheckContrastScale(*contrast_scale);  // replaces self_referenced's
  const double log_offset = self_referenced.log_offset_fraction;
  UWS_USAGE_CHECK(
      log_offset >= 0.0 && log_offset <= fusion::SelfReferencedOptions::kMaxLogOffsetFraction,
      "--log-offset must be in [0, ", fusion::SelfReferencedOptions::kMaxLogOffsetFraction,
      "] (of the tracked image's mean; 0 = linear), got ", log_offset);
  if (smoothing_half_window && *smoothing_half_window < 0) {
    throw UsageError("--smoothing-half-window must be >= 0 (0 = raw poses) or auto, got " +
                     std::to_string(*smoothing_half_window));
  }
  if (self_referenced.init_refinements < 0) {
    throw UsageError("--init-refinements must be >= 0, got " +
                     std::to_string(self_referenced.init_refinements));
  }
  if (self_referenced.max_init_refinements < self_referenced.init_refinements) {
    throw UsageError("--max-init-refinements (" +
                     std::to_string(self_referenced.max_init_refinements) +
                     ") must be at least --init-refinements (" +
                     std::to_string(self_referenced.init_refinements) + ")");
  }
  if (!(max_range_error_per_px >= 0.0) || !std::isfinite(max_range_error_per_px)) {
    throw UsageError(fmt::format("--max-range-error-per-px must be >= 0 (0 = keep all), got {}",
                                 max_range_error_per_px));
  }
  if (passes < 0 || passes > kMaxPasses) {
    throw UsageError(fmt::format("--passes must be auto or 1 to {}, got {}", kMaxPasses, passes));
  }
  if (live && (passes != 1 || retry_smaller_tracking)) {
    throw UsageError(
        "a live run is processed once: it needs --passes 1 and no retry on half the image");
  }
  if (live_max_lag_s && !live) throw UsageError("--live-max-lag needs a live run (--live)");
  if (live_max_lag_s && !(*live_max_lag_s > 0.0 && std::isfinite(*live_max_lag_s)))
    throw UsageError(fmt::format("--live-max-lag must be > 0 s, got {}", *live_max_lag_s));
  if (!(passes_settled_m > 0.0) || !(passes_settled_deg > 0.0) ||
      !(passes_converging_ratio > 0.0 && passes_converging_ratio <= 1.0)) {
    throw UsageError("the passes' tolerances must be > 0 and their converging ratio in (0, 1]");
  }
  if (passes > 1 && poses_file)
    throw UsageError("--passes " + std::to_string(passes) +
                     " and --poses exclude each other (the passes are the odometry's)");
  if (!std::isfinite(poses_time_offset_s))
    throw UsageError("--poses-time-offset must be a finite number of seconds");
  if ((poses_time_offset_s != 0.0 || poses_body_from_camera) && !poses_file)
    throw UsageError(std::string(poses_time_offset_s != 0.0 ? "--poses-time-offset"
                                                            : "--poses-body-from-camera") +
                     " needs --poses (it says how to read that trajectory)");
  if ((oracle_depths || oracle_tracks) && poses_file)
    throw UsageError(std::string(oracle_depths ? "--oracle-depths" : "--oracle-tracks") +
                     " and --poses exclude each other (the oracle feeds the odometry, which "
                     "--poses replaces)");
}

namespace {

// Whether the whole of `text` reads as a number (std::stoi / std::stod).
template <typename T>
bool ReadWhole(const std::string& text, T* value) {
  size_t used = 0;
  try {
    if constexpr (std::is_integral_v<T>) {
      *value = std::stoi(text, &used);
    } else {
      *value = std::stod(text, &used);
    }
  } catch (const std::exception&) {
    return false;
  }
  return used == text.size() && !text.empty();
}

// The fewest N >= 1 that keep every Nth of the frames at or below
// `max_rate_hz`, from their mean interval; `otherwise` with no time
// between them.
int FewestToKeepRate(const std::vector<FrameRecord>& frames, double max_rate_hz, int otherwise) {
  const double interval_s = MeanFrameInterval(frames);
  if (!(interval_s > 0.0)) return otherwise;  // fewer than two frames, or no time between them
  return std::max(1, static_cast<int>(std::ceil(1.0 / interval_s / max_rate_hz - 1e-9)));
}

}  // namespace

Rigid3d ParseBodyFromCamera(const std::string& value) {
  double n[7];
  char tail = 0;
  if (std::sscanf(value.c_str(), "%lf,%lf,%lf,%lf,%lf,%lf,%lf%c", &n[0], &n[1], &n[2], &n[3], &n[4],
                  &n[5], &n[6], &tail) != 7 ||
      !std::all_of(std::begin(n), std::end(n), [](double x) { return std::isfinite(x); }))
    throw UsageError("--poses-body-from-camera must be seven numbers tx,ty,tz,qx,qy,qz,qw, got '" +
                     value + "'");
  const Eigen::Quaterniond q(n[6], n[3], n[4], n[5]);
  if (!(std::abs(q.norm() - 1.0) <= 1e-3))
    throw UsageError(
        "--poses-body-from-camera: qx,qy,qz,qw must be a unit quaternion, its norm is " +
        std::to_string(q.norm()));
  return Rigid3d(q.normalized(), Eigen::Vector3d(n[0], n[1], n[2]));
}

int ParseTrackEvery(const std::string& value, const std::string& flag) {
  if (value == "auto") return 0;
  int count = 0;
  if (!ReadWhole(value, &count) || count < 1)
    throw UsageError(flag + " must be auto or a count >= 1, got '" + value + "'");
  return count;
}

std::optional<double> ParseContrastScale(const std::string& value) {
  if (value == "auto") return std::nullopt;
  double fraction = 0.0;
  if (!ReadWhole(value, &fraction))
    throw UsageError("--contrast-scale must be auto or a fraction in [0, 0.5], got '" + value +
                     "'");
  CheckContrastScale(fraction);
  return fraction;
}

int ResolveTrackEvery(int track_every, const std::vector<FrameRecord>& frames) {
  if (track_every > 0) return track_every;
  return FewestToKeepRate(frames, ReconstructJob::kMaxTrackedRateHz, 1);
}

int ResolveStartScreenEvery(int start_screen_every, int track_every,
                            const std::vector<FrameRecord>& frames) {
  if (start_screen_every > 0) return start_screen_every;
  return std::max(track_every,
                  FewestToKeepRate(frames, ReconstructJob::kMaxStartScreenRateHz, track_every));
}

std::optional<int> ParseSmoothingHalfWindow(const std::string& value) {
  if (value == "auto") return std::nullopt;
  int count = 0;
  if (!ReadWhole(value, &count) || count < 0)
    throw UsageError("--smoothing-half-window must be >= 0 (0 = raw poses) or auto, got '" + value +
                     "'");
  return count;
}

double StartPlaneViewCosine(double max_angle_deg) {
  if (!(max_angle_deg > 0 && max_angle_deg <= 90)) {
    throw UsageError(
        fmt::format("--max-start-plane-angle must be in (0, 90] deg, got {}", max_angle_deg));
  }
  return max_angle_deg == 90 ? 0.0 : std::cos(max_angle_deg * M_PI / 180.0);
}

double DefaultMaxStartPlaneAngleDeg() {
  return std::acos(fusion::SelfReferencedOptions().min_start_plane_view_cosine) * 180.0 / M_PI;
}

int ResolveSmoothingHalfWindow(std::optional<int> half_window,
                               const std::vector<FrameRecord>& frames) {
  if (half_window) return *half_window;
  const int frames_count = fusion::SelfReferencedOptions().smoothing_half_window;
  const double interval_s = MeanFrameInterval(frames);
  if (!(interval_s > 0.0)) return frames_count;
  const long within_span = std::lround(ReconstructJob::kSmoothingMaxHalfSpanS / interval_s);
  return static_cast<int>(std::min<long>(frames_count, within_span));
}

bool ResolveAsyncBundleAdjustment(std::optional<bool> async,
                                  const std::vector<FrameRecord>& frames) {
  return async.value_or(vo::AsyncBundleAdjustmentByDefault(MeanFrameInterval(frames)));
}

}  // namespace uwscan
