#include "uwscan/pipeline/vo_run.h"

#include <fmt/format.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <iostream>
#include <map>
#include <opencv2/imgproc.hpp>

#include "uwscan/eval/port_analysis.h"
#include "uwscan/fusion/self_referenced.h"
#include "uwscan/io/image.h"
#include "uwscan/io/tum_trajectory.h"
#include "uwscan/laser/detector.h"
#include "uwscan/pipeline/laser_detect.h"
#include "uwscan/pipeline/vo_dataset.h"
#include "uwscan/util/atomic_file.h"
#include "uwscan/util/error.h"
#include "uwscan/util/interrupt.h"
#include "uwscan/util/stopwatch.h"

namespace uwscan {
namespace {

long ProcStatusKb(const char* key) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(key, 0) == 0) return std::stol(line.substr(std::string(key).size()));
  }
  return 0;
}

std::string CsvSafe(std::string text) {
  for (char& c : text) {
    if (c == ',' || c == '\n') c = ';';
  }
  return text;
}

}  // namespace

long CurrentRssKb() { return ProcStatusKb("VmRSS:"); }
long PeakRssKb() { return ProcStatusKb("VmHWM:"); }

void VoJob::Check() const {
  CheckSampleBitsOption(sample_bits);
  if (model != "flatport" && model != "pinhole") {
    throw UsageError("--model must be flatport or pinhole, not '" + model + "'");
  }
  CheckViewingDistanceOption("--pinhole-fit-depth", pinhole_fit_depth_m, 0.05);
  UWS_USAGE_CHECK(std::isfinite(mask_margin_px) && mask_margin_px >= 0,
                  "--mask-margin must be a number of pixels >= 0, got ", mask_margin_px);
  if (max_tracking_width < 0) throw UsageError("--max-tracking-width must be >= 0");
  if (max_frames < 0) {
    throw UsageError("--max-frames must be >= 0 (0 = all), got " + std::to_string(max_frames));
  }
  CheckContrastScale(contrast_sigma_fraction);
  CheckOdometryFlags(odometry);
  odometry.Check();
}

void CheckContrastScale(double fraction) {
  if (!(fraction >= 0 && fraction <= 0.5)) {
    throw UsageError("--contrast-scale must be in [0, 0.5] (a fraction of the image width), got " +
                     fmt::format("{}", fraction));
  }
}

void CheckOdometryFlags(const vo::OdometryOptions& odometry) {
  const vo::BundleAdjustmentOptions& ba = odometry.ba;
  if (ba.window_size <= ba.num_fixed_keyframes) {
    throw UsageError("--window must be at least " + std::to_string(ba.num_fixed_keyframes + 1) +
                     " (the window's oldest " + std::to_string(ba.num_fixed_keyframes) +
                     " keyframes are held fixed), got " + std::to_string(ba.window_size));
  }
  if (!(ba.max_solver_time_s > 0) || !std::isfinite(ba.max_solver_time_s))
    throw UsageError(fmt::format("--ba-time-limit must be a finite number of seconds > 0, got {}",
                                 ba.max_solver_time_s));
  if (ba.max_iterations < 1) throw UsageError("--ba-iterations must be >= 1");
  if (ba.history_keyframes < 0) {
    throw UsageError("--ba-history must be >= 0, got " + std::to_string(ba.history_keyframes));
  }
  const vo::FeatureTrackerOptions& tracker = odometry.tracker;
  if (tracker.klt_window_px < vo::kMinWindowPx || tracker.klt_window_px > vo::kMaxWindowPx ||
      tracker.klt_window_px % 2 == 0) {
    throw UsageError(fmt::format("--klt-window must be odd, {} to {}, got {}", vo::kMinWindowPx,
                                 vo::kMaxWindowPx, tracker.klt_window_px));
  }
  if (tracker.max_per_cell < 1)
    throw UsageError("--per-cell must be >= 1, got " + std::to_string(tracker.max_per_cell));
  if (tracker.max_dormant_frames < 0) {
    throw UsageError("--max-dormant-frames must be >= 0, got " +
                     std::to_string(tracker.max_dormant_frames));
  }
  CheckViewingDistanceOption("--initial-depth", odometry.initial_median_depth_m, 0.0);
}

VoRunSummary RunVisualOdometry(const VoJob& job) {
  InterruptibleScope interruptible;
  job.Check();
  const auto start = std::chrono::steady_clock::now();
  const VoDataset dataset = ReadVoDataset(job.dataset_dir);
  {
    std::vector<std::filesystem::path> inputs = {
        dataset.dir / "frames.csv", dataset.dir / "rig.yaml", dataset.dir / "groundtruth.tum"};
    for (const FrameRecord& frame : dataset.frames) inputs.push_back(dataset.dir / frame.file);
    RefuseOutputOntoInput("--out", job.trajectory_out, inputs);
    if (job.status_out) RefuseOutputOntoInput("--status", *job.status_out, inputs);
  }
  const Camera& rig_camera = dataset.rig.CameraByName(job.camera_name);
  size_t camera_index = 0;
  while (dataset.rig.cameras[camera_index].name != rig_camera.name) ++camera_index;
  Camera camera = rig_camera;
  if (job.model == "pinhole" && camera.IsFlatPort()) {
    PinholeFitOptions fit;
    fit.depth_m = job.pinhole_fit_depth_m;
    camera = FitPinholeToFlatPort(rig_camera, fit).pinhole;
  } else if (job.model == "flatport" && !camera.IsFlatPort()) {
    throw UsageError("--model flatport needs a flat-port camera, " + rig_camera.name +
                     " in rig.yaml is a pinhole");
  }
  laser::DetectorOptions detector;
  if (job.mask_laser) {
    if (dataset.rig.lasers.empty()) {
      throw UsageError("--mask-laser needs a laser in " + (job.dataset_dir / "rig.yaml").string());
    }
    detector.scan_rows =
        LaserLineIsVertical(rig_camera, dataset.rig.CameraFromLaser(camera_index, 0));
    detector.laser_channel = laser::ChannelForWavelength(dataset.rig.lasers[0].wavelength_nm);
  }

  // Wide frames are tracked smaller, as in the self-referenced scan; a raw
  // Bayer frame through the passive colour's own samples (half resolution,
  // no demosaicking: the interpolated pixels add no information but cost
  // 4x the tracking).
  using Tracking = fusion::SelfReferencedPoseProvider;
  const int passive_rgb = Tracking::PassiveColour(detector.laser_channel);
  const int halvings = Tracking::TrackingHalvings(rig_camera.width, job.max_tracking_width);
  const std::optional<cv::Point> bayer_offset =
      halvings > 0 ? Tracking::BayerSampleOffset(rig_camera.bayer, passive_rgb) : std::nullopt;
  if (halvings > 0) camera = Tracking::TrackingCamera(camera, halvings, bayer_offset);
  const cv::Size tracked_size(camera.width, camera.height);

  vo::OdometryOptions odometry_options = job.odometry;
  const size_t n = dataset.frames.size();
  const double mean_interval_s =
      n > 1 ? (dataset.frames.back().timestamp_s - dataset.frames.front().timestamp_s) / (n - 1)
            : 0.0;
  odometry_options.async_bundle_adjustment =
      job.async_bundle_adjustment.value_or(vo::AsyncBundleAdjustmentByDefault(mean_interval_s));
  vo::Odometry odometry(camera, odometry_options);
  VoRunSummary summary;
  summary.async_bundle_adjustment = odometry_options.async_bundle_adjustment;
  summary.tracked_image =
      (bayer_offset
           ? std::string(passive_rgb == laser::kRed ? "red" : "blue") + " samples of the raw mosaic"
           : std::string("passive colour")) +
      ", " + std::to_string(camera.width) + "x" + std::to_string(camera.height) +
      (job.contrast_sigma_fraction > 0 ? ", contrast equalised" : "");
  std::map<int, StampedPose> poses;  // by position in frames.csv
  std::vector<vo::FrameResult> results;
  std::vector<std::string> status_lines;
  std::vector<std::string> reasons;  // per frame: status and message
  const bool progress = !job.quiet && isatty(STDERR_FILENO);
  const int total = job.max_frames == 0 ? int(dataset.frames.size())
                                        : std::min(job.max_frames, int(dataset.frames.size()));
  size_t after_first_frame = 0;  // warnings up to the first frame's doubts
  auto warn = [&](const std::string& message) {
    if (summary.warnings.size() < 20) summary.warnings.push_back(message);
  };
  const std::string slow =
      SlowFramesWarning(FindFrameGaps(dataset.frames), (dataset.dir / "frames.csv").string());
  if (!slow.empty()) warn(slow);
  for (int i = 0; i < total; ++i) {
    const FrameRecord& entry = dataset.frames[size_t(i)];
    cv::Mat raw = ReadFrameImage(dataset, entry);
    PrepareFrame(&raw, job.sample_bits, dataset.dir / entry.file);
    if (raw.empty()) {
      ++summary.unreadable;
      warn("frame " + std::to_string(entry.index) + ": cannot read " + entry.file);
    } else if (summary.unreadable == i) {  // the first frame read
      const FrameDoubts doubts = InspectFrame(raw, dataset.dir / entry.file, rig_camera.bayer,
                                              /*from_rig=*/true, job.sample_bits);
      for (const std::string& warning : doubts.Warnings()) warn(warning);
      after_first_frame = summary.warnings.size();
    }
    cv::Mat mask;
    if (job.mask_laser && !raw.empty() && raw.cols == rig_camera.width &&
        raw.rows == rig_camera.height) {
      const auto t0 = std::chrono::steady_clock::now();
      try {
        const laser::Detection detection = laser::DetectLaserLine(
            raw, laser::LayoutFor(rig_camera.bayer, raw.channels()), detector);
        mask = detection.mask;
        if (!mask.empty() && job.mask_margin_px > 0) {
          const int r = int(std::ceil(job.mask_margin_px));
          cv::dilate(mask, mask,
                     cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * r + 1, 2 * r + 1)));
        }
      } catch (const Error& e) {
        warn("frame " + std::to_string(entry.index) + ": laser mask: " + e.what());
      }
      summary.mask_s += SecondsSince(t0);
    }
    // Track the colour the laser does not light (the LED's, §5.5), with the
    // moving lights' shading removed (fusion::SelfReferencedPoseProvider).
    cv::Mat tracking;
    const bool rig_size = raw.cols == rig_camera.width && raw.rows == rig_camera.height;
    if (!raw.empty() && halvings > 0 && rig_size) {
      if (bayer_offset && raw.channels() != 1) {
        warn("frame " + std::to_string(entry.index) + ": a " + std::to_string(raw.channels()) +
             "-channel image where rig.yaml says raw '" + rig_camera.bayer + "' frames");
      } else {
        tracking = Tracking::NormalizeIllumination(
            Tracking::TrackedPassiveImage(raw, rig_camera.bayer, detector.laser_channel,
                                          bayer_offset, tracked_size),
            0.01 * camera.width, job.contrast_sigma_fraction * camera.width);
      }
      mask = Tracking::TrackedMask(mask, tracked_size);
    } else if (!raw.empty() && halvings > 0) {
      warn("frame " + std::to_string(entry.index) + ": " +
           ImageSizeMismatch(rig_camera, raw.cols, raw.rows));
    } else if (!raw.empty()) {
      // (A frame of the wrong size goes through as it is: the odometry
      // reports it invalid.)
      tracking = fusion::SelfReferencedPoseProvider::NormalizeIllumination(
          fusion::SelfReferencedPoseProvider::PassiveImage(raw, rig_camera.bayer,
                                                           detector.laser_channel),
          0.01 * rig_camera.width, job.contrast_sigma_fraction * rig_camera.width);
    }
    vo::FrameResult result = odometry.ProcessFrame(tracking, mask, entry.timestamp_s);
    summary.vo_s += result.total_time_s;
    summary.tracking_s += result.tracking_time_s;
    summary.vo_cpu_s += result.total_cpu_s;
    summary.bundle_adjustment_s += result.bundle_adjustment.time_s;
    if (result.bundle_adjustment.keyframes > 0) ++summary.bundle_adjustments;
    summary.bundle_adjustments_time_limited += result.bundle_adjustment.time_limited;
    summary.tracking_cpu_s += result.tracking_cpu_s;
    for (const auto& [frame, pose] : result.earlier_poses) {
      poses[frame] = {dataset.frames[size_t(frame)].timestamp_s, pose};
    }
    if (result.world_from_camera) poses[i] = {entry.timestamp_s, *result.world_from_camera};
    switch (result.status) {
      case vo::FrameStatus::kTracked:
        ++summary.tracked;
        break;
      case vo::FrameStatus::kLost:
        ++summary.lost;
        break;
      case vo::FrameStatus::kReinitialized:
        ++summary.reinitialised;
        break;
      case vo::FrameStatus::kInvalid:
        ++summary.invalid;
        break;
      case vo::FrameStatus::kInitializing:
        break;
    }
    if (result.status == vo::FrameStatus::kInvalid ||
        (result.status == vo::FrameStatus::kLost && !result.message.empty() &&
         result.message != "re-initialising")) {
      warn("frame " + std::to_string(entry.index) + ": " + vo::FrameStatusName(result.status) +
           ": " + result.message);
    }
    reasons.push_back(std::string(vo::FrameStatusName(result.status)) +
                      (result.message.empty() ? "" : ": " + result.message));
    summary.keyframes += result.keyframe;
    summary.tracks_lost_on_mask += result.tracking.lost_mask;
    summary.tracks_reacquired += result.tracking.reacquired;
    status_lines.push_back(std::to_string(entry.index) + "," + std::to_string(entry.timestamp_s) +
                           "," + vo::FrameStatusName(result.status) + "," +
                           std::to_string(int(result.keyframe)) + "," +
                           std::to_string(result.tracks) + "," + std::to_string(result.inliers) +
                           "," + CsvSafe(result.message));
    if (i == total / 10) summary.rss_kb_at_10_percent = CurrentRssKb();
    if (progress && (i % 50 == 0 || i + 1 == total)) {
      std::cerr << "\rvo: frame " << i + 1 << "/" << total << " (" << summary.tracked
                << " tracked, " << summary.lost << " lost)" << std::flush;
    }
    ThrowIfInterrupted();
  }
  if (progress) std::cerr << "\n";
  summary.frames = total;

  // Trajectory with the gaps (runs of frames without a pose) marked.
  TumTrajectory trajectory;
  std::string gap_reason;
  int gap_begin = -1;
  for (int i = 0; i <= total; ++i) {
    const bool posed = i < total && poses.count(i);
    if (i < total && !posed) {
      if (gap_begin < 0) gap_begin = i;
      if (gap_reason.empty()) gap_reason = reasons[size_t(i)];
      continue;
    }
    if (gap_begin >= 0) {
      trajectory.gaps.push_back({dataset.frames[size_t(gap_begin)].timestamp_s,
                                 dataset.frames[size_t(i - 1)].timestamp_s, gap_reason});
      gap_begin = -1;
      gap_reason.clear();
    }
    if (posed) trajectory.poses.push_back(poses[i]);
  }
  summary.posed = int(trajectory.poses.size());
  summary.gaps = int(trajectory.gaps.size());
  // Monocular VO starts once the features have moved by
  // init_parallax_fraction of the image: a hover may never get there.
  const std::string initializing = vo::FrameStatusName(vo::FrameStatus::kInitializing);
  int waited = 0;
  for (int i = 0; i < total; ++i)
    waited += !poses.count(i) && reasons[size_t(i)].rfind(initializing, 0) == 0;
  if (total > 0 && waited >= 0.25 * total) {
    const std::string why = fmt::format(
        "monocular odometry starts once the features have moved {:g} % of the image width (the "
        "camera moving sideways); `uwscan reconstruct` starts from the laser's ranges instead",
        100.0 * odometry_options.init_parallax_fraction);
    summary.warnings.insert(  // after how the frames are read, which may say why
        summary.warnings.begin() + static_cast<std::ptrdiff_t>(after_first_frame),
        summary.posed == 0 ? "the odometry never started: " + why
                           : fmt::format("{} of the {} frames ({:.0f} %) got no pose while the "
                                         "odometry waited to start: {}",
                                         waited, total, 100.0 * waited / total, why));
  }
  StagedFiles outputs;
  outputs.Add(job.trajectory_out, TumTrajectoryToText(trajectory));
  if (job.status_out) {
    std::string text = "frame,timestamp_s,status,keyframe,tracks,inliers,message\n";
    for (const std::string& line : status_lines) text += line + "\n";
    outputs.Add(*job.status_out, text);
  }
  outputs.Commit();
  if (dataset.ground_truth && trajectory.poses.size() >= 3) {
    try {
      summary.metrics = ComputeTrajectoryMetrics(trajectory.poses, dataset.ground_truth->poses);
    } catch (const Error& e) {
      warn(std::string("evaluation: ") + e.what());
    }
  }
  summary.rss_kb_end = CurrentRssKb();
  summary.peak_rss_kb = PeakRssKb();
  summary.wall_s = SecondsSince(start);
  return summary;
}

}  // namespace uwscan
