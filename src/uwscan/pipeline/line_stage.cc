#include "uwscan/pipeline/line_stage.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "uwscan/fusion/self_referenced.h"
#include "uwscan/io/image.h"
#include "uwscan/laser/clipping.h"
#include "uwscan/pipeline/laser_detect.h"
#include "uwscan/util/error.h"
#include "uwscan/util/stopwatch.h"

namespace uwscan {
namespace fs = std::filesystem;

bool LaserSweeps(const std::vector<FrameRecord>& frames) {
  return std::any_of(frames.begin(), frames.end(), [&](const FrameRecord& f) {
    return f.laser_angle_rad && frames.front().laser_angle_rad &&
           std::abs(*f.laser_angle_rad - *frames.front().laser_angle_rad) > 1e-6;
  });
}

LineStage::LineStage(const ReconstructJob& job, fs::path dataset, const Camera& camera,
                     const LineProjector& laser, const Rigid3d& camera_from_laser,
                     const std::vector<FrameRecord>& frames, ReconstructReport* report)
    : job_(job),
      dataset_(std::move(dataset)),
      camera_(camera),
      laser_(laser),
      camera_from_laser_(camera_from_laser),
      frames_(frames),
      report_(report) {
  detector_ = job.detector;
  detector_.scan_rows = LaserLineIsVertical(camera, camera_from_laser);
  detector_.laser_channel = laser::ChannelForWavelength(laser.wavelength_nm);
  detector_.albedo_channel =
      job.drop_albedo_edges ? laser::AlbedoChannelFor(detector_.laser_channel) : -1;
  if (!job.drop_off_colour) detector_.min_signature_share = 0.0;
  detector_.make_mask = true;
  if (job.texture_filter) {
    if (LaserSweeps(frames)) {
      StartSweepFilter();
    } else {
      laser::MotionFilterOptions motion;
      motion.scan_rows = detector_.scan_rows;
      motion.epipolar = job.epipolar_texture;
      motion_filter_.emplace(camera, motion);
    }
  }
  // The motion filter judges the candidates of whole scan lines. (Set
  // only now: the sweep filter's frame ahead is searched whole.)
  windowed_ = job.line_window_px > 0 && !motion_filter_;
  if (windowed_) detector_.line_window_px = job.line_window_px;
  report_->line_window_px = windowed_ ? job.line_window_px : 0;
  report_->max_range_error_per_px = job.max_range_error_per_px;
  report_->sample_bits = job.sample_bits;
}

cv::Mat LineStage::ReadFrameImage(size_t i) const {
  const fs::path file = dataset_ / frames_[i].file;
  cv::Mat image = ReadImage(file);
  PrepareFrame(&image, job_.sample_bits, file);
  return image;
}

void LineStage::InspectFirstFrame(const cv::Mat& image, const fs::path& file) {
  first_image_type_ = image.type();
  if (report_->first_frame.file.empty()) {  // the main camera's, run first
    report_->first_frame =
        InspectFrame(image, file, camera_.bayer, /*from_rig=*/true, job_.sample_bits);
  }
}

void LineStage::SetPose(int frame, const Rigid3d& world_from_camera) {
  if (motion_filter_) motion_filter_->SetPose(frame, world_from_camera);
}

void LineStage::Process(size_t i, const cv::Mat& image, laser::Detection* detection,
                        laser::Profile* profile) {
  const FrameRecord& record = frames_[i];
  UWS_CHECK(image.cols == camera_.width && image.rows == camera_.height,
            (dataset_ / record.file).string(), ": ",
            ImageSizeMismatch(camera_, image.cols, image.rows));
  if (first_image_type_ < 0) InspectFirstFrame(image, dataset_ / record.file);
  // One colour frame among raw Bayer ones (or a 16-bit one among 8-bit
  // ones) is another camera's or another export's: its colours and levels
  // would be read as the others'.
  UWS_CHECK(image.type() == first_image_type_, (dataset_ / record.file).string(), ": a ",
            ImageTypeName(image.type()), " image, but the frames before are ",
            ImageTypeName(first_image_type_), " (", (dataset_ / frames_.front().file).string(),
            ")");
  auto t = std::chrono::steady_clock::now();
  // Interleaved scans (frames.csv laser_on, thesis §5.4): nothing to detect
  // with the laser off; with it on, the line is found in the difference to
  // the previous (laser-off) frame, where the scene's own texture, a
  // painted stripe or the ambient light cancel.
  const bool laser_off = record.LaserOff();
  const bool difference = job_.detect_on_difference && record.laser_on && !laser_off;
  *detection = {};
  if (difference && (i == 0 || dark_image_.empty() || dark_frame_ != i - 1)) {
    // No laser-off frame just before (the first frame): the line is not
    // looked for in the raw image, where the scene could pass for it.
  } else if (!laser_off) {
    cv::Mat lit_only;
    if (difference) {
      cv::subtract(image, dark_image_, lit_only);  // saturates at 0
      *detection = Detect(lit_only, record);
      ++report_->frames_on_difference;
      if (!laser_on_checked_) {
        lit_image_ = image;
        lit_frame_ = i;
        lit_points_ = detection->points.size();
      }
    } else {
      *detection = Detect(image, record);
    }
    if (!laser_colour_checked_) CheckLaserColour(difference ? lit_only : image, *detection);
    report_->static_detections_removed += detection->stats.excluded_candidates;
    report_->albedo_edge_points += detection->stats.albedo_edge_points;
    report_->off_colour_points += detection->stats.off_colour_peaks;
    report_->frames_with_off_colour += detection->stats.off_colour_segments > 0;
    // Noise and texture peaks are ignored now and then on any scene; a
    // stripe or reflection shows on many scan lines of a frame.
    report_->frames_with_static_detections +=
        detection->stats.excluded_candidates >= 0.05 * ScanLines();
    report_->frames_sweep_filter_restored += detection->stats.exclusion_restored;
    // In the raw image: a difference image cancels the clipped scene, not
    // the line hidden in it.
    const laser::ColourLayout layout = laser::LayoutFor(camera_.bayer, image.channels());
    const laser::ClippedScene clipped = laser::MeasureClipping(
        image, layout, detector_.laser_channel, detector_.scan_rows, detection->points);
    report_->clipped_samples += clipped.clipped;
    report_->clipping_samples_examined += clipped.examined;
    ++report_->frames_clipping_examined;
    report_->frames_with_clipped_scene += clipped.Share() >= laser::kClippedFrameShare;
    // The features' colour (a mono camera's is the laser's, above).
    if (layout != laser::ColourLayout::kMono) {
      const int colour = fusion::SelfReferencedPoseProvider::PassiveColour(detector_.laser_channel);
      const laser::ClippedScene features =
          laser::MeasureClipping(image, layout, colour, detector_.scan_rows, detection->points);
      report_->features_clipped_samples += features.clipped;
      report_->features_clipping_samples_examined += features.examined;
      ++report_->frames_features_clipping_examined;
      report_->frames_with_clipped_features +=
          features.Share() >= laser::kClippedFeaturesFrameShare;
      report_->features_colour = laser::ChannelName(colour);
    }
  } else {
    ++report_->frames_laser_off;
    dark_image_ = image;
    dark_frame_ = i;
    if (!laser_on_checked_ && !lit_image_.empty() && lit_frame_ + 1 == i) CheckLaserOn(i);
  }
  report_->seconds_detect += SecondsSince(t);

  t = std::chrono::steady_clock::now();
  const double angle = record.laser_angle_rad.value_or(0.0);
  *profile = laser::TriangulateProfile(
      camera_, laser_, laser::CameraFromLaserAtAngle(camera_from_laser_, angle), detection->points,
      record.index, job_.max_range_error_per_px);
  if (motion_filter_ && !laser_off && !detection->candidates.empty()) {
    motion_filter_->End(detection->candidates, *profile);
    detection->candidates = {};
  }
  if (!laser_pose_checked_ && detection->points.size() >= laser::kPoseCheckPoints) {
    laser_pose_checked_ = true;
    report_->laser_pose_inverse_fits =
        laser::InverseLaserPoseFits(camera_, laser_, camera_from_laser_, angle, detection->points,
                                    *profile, job_.max_range_error_per_px);
  }
  report_->triangulation_failures += profile->failed;
  report_->grazing_points += profile->grazing;
  report_->seconds_triangulate += SecondsSince(t);
}

void LineStage::CheckLaserColour(const cv::Mat& image, const laser::Detection& detection) {
  laser_colour_checked_ = true;
  const int seen = laser::OtherColourOfTheLine(
      image, laser::LayoutFor(camera_.bayer, image.channels()), detector_, detection.points.size());
  if (seen >= 0) {
    report_->laser_seen_in = laser::ChannelName(seen);
    report_->laser_colour_warning =
        laser::LaserColourWarning(seen, detector_.laser_channel, laser_.wavelength_nm);
  }
}

void LineStage::CheckLaserOn(size_t i) {
  laser_on_checked_ = true;
  cv::Mat reversed;
  cv::subtract(dark_image_, lit_image_, reversed);
  const size_t found =
      laser::DetectLaserLine(reversed, laser::LayoutFor(camera_.bayer, reversed.channels()),
                             detector_)
          .points.size();
  lit_image_ = cv::Mat();
  if (found >= laser::kPoseCheckPoints && found >= 4 * lit_points_)
    report_->laser_on_inverted_at = static_cast<int>(frames_[i].index);
}

// The line in one frame; on servo scans, candidates standing where
// candidates stood while the sheet turned are a stripe or reflection, not
// the line (§5.5), and where nearly all would go (the line runs along a
// stripe) only what stands exactly where the stripe stood is left out.
laser::Detection LineStage::Detect(const cv::Mat& image, const FrameRecord& record) {
  laser::DetectorOptions options = detector_;
  const bool sweeping = sweep_filter_ && record.laser_angle_rad;
  if (sweeping) {
    sweep_filter_->Begin(record.timestamp_s, *record.laser_angle_rad);
    options.exclude_candidate = sweep_filter_->Predicate();
    options.exclude_candidate_on_restore = sweep_filter_->Predicate(/*strict=*/true);
    options.keep_candidates = true;
  } else if (motion_filter_) {
    // Its candidates are remembered with the profile's depths (Process).
    motion_filter_->Begin(record.index, record.timestamp_s);
    options.exclude_candidate = motion_filter_->Predicate();
    options.exclude_candidate_on_restore = motion_filter_->Predicate(/*strict=*/true);
    options.keep_candidates = true;
    report_->texture_epipolar_matches = motion_filter_->epipolar_matches_total();
  }
  const auto layout = laser::LayoutFor(camera_.bayer, image.channels());
  laser::Detection detection;
  if (windowed_ && prior_lines_ > 0 && windowed_frames_ < kWholeScanEvery - 1) {
    options.line_prior = line_prior_;
    detection = laser::DetectLaserLine(image, layout, options);
    ++windowed_frames_;
    if (OffThePrior(detection)) {
      // Something new: found as on whole scan lines, where it competes
      // with everything they hold.
      options.line_prior.clear();
      detection = laser::DetectLaserLine(image, layout, options);
      windowed_frames_ = 0;
      ++report_->frames_line_window_redone;
    }
  } else {
    detection = laser::DetectLaserLine(image, layout, options);
    windowed_frames_ = 0;
  }
  if (windowed_) {
    line_prior_.assign(ScanLines(), {std::numeric_limits<float>::quiet_NaN(), 0.0f});
    prior_lines_ = 0;
    const auto add = [&](const laser::LaserPoint& p) {
      const auto [line, position] = OnScanLine(p);
      if (line < 0 || line >= static_cast<int>(line_prior_.size())) return;
      auto& [from, to] = line_prior_[line];
      if (std::isnan(from)) from = to = position, ++prior_lines_;
      from = std::min(from, position), to = std::max(to, position);
    };
    for (const auto& p : detection.points) add(p);
    for (const auto& p : detection.albedo_edge_points) add(p);
  }
  if (sweeping) {
    sweep_filter_->End(detection.candidates);
    detection.candidates = {};
  }
  return detection;
}

std::pair<int, float> LineStage::OnScanLine(const laser::LaserPoint& p) const {
  return detector_.scan_rows
             ? std::pair{static_cast<int>(std::lround(p.v)), static_cast<float>(p.u)}
             : std::pair{static_cast<int>(std::lround(p.u)), static_cast<float>(p.v)};
}

bool LineStage::OffThePrior(const laser::Detection& detection) const {
  // A point on a scan line without a prior continues the line if it lies
  // within the window of the prior of a scan line nearby (the line grown
  // at its ends, or gone on from one side of a silhouette to the other's);
  // otherwise something appeared.
  const int lines = static_cast<int>(line_prior_.size());
  const float window = static_cast<float>(detector_.line_window_px);
  const auto off = [&](const laser::LaserPoint& p) {
    const auto [line, position] = OnScanLine(p);
    if (line < 0 || line >= lines || std::isfinite(line_prior_[line].first)) return false;
    for (int l = std::max(0, line - kPriorNeighbourLines);
         l <= std::min(lines - 1, line + kPriorNeighbourLines); ++l) {
      const auto [from, to] = line_prior_[l];
      if (position >= from - window && position <= to + window) return false;  // NaN: false
    }
    return true;
  };
  return std::any_of(detection.points.begin(), detection.points.end(), off) ||
         std::any_of(detection.albedo_edge_points.begin(), detection.albedo_edge_points.end(), off);
}

void LineStage::StartSweepFilter() {
  laser::SweepFilterOptions sweep;
  sweep.scan_rows = detector_.scan_rows;
  sweep.focal_px = detector_.scan_rows ? camera_.intrinsics[0] : camera_.intrinsics[1];
  sweep_filter_.emplace(sweep);
  // The first frames have no earlier frame the sheet has turned far
  // enough from: remember the candidates of the first later frame that
  // is (a fraction of a second ahead, the platform has hardly moved), so
  // that a stripe is recognised from the first frame on. Interleaved
  // scans need no such help (their difference images hold no stripe).
  const bool interleaved = !frames_.empty() && frames_.front().laser_on.has_value();
  if (interleaved || frames_.empty() || !frames_.front().laser_angle_rad) return;
  const double start = *frames_.front().laser_angle_rad;
  for (size_t k = 1;
       k < frames_.size() && sweep.WithinLag(frames_[k].timestamp_s - frames_.front().timestamp_s);
       ++k) {
    if (!frames_[k].laser_angle_rad ||
        sweep.focal_px * std::abs(*frames_[k].laser_angle_rad - start) <
            2.0 * sweep.min_expected_shift_px) {
      continue;
    }
    const cv::Mat ahead = ReadFrameImage(k);
    if (ahead.cols != camera_.width || ahead.rows != camera_.height) break;  // reported later
    Detect(ahead, frames_[k]);  // remembered by the filter
    break;
  }
}

void AddFurtherCameraLineCounts(const ReconstructReport& further, ReconstructReport* report) {
  ReconstructReport& r = *report;
  r.frames_on_difference += further.frames_on_difference;
  r.frames_laser_off += further.frames_laser_off;
  r.frames_line_window_redone += further.frames_line_window_redone;
  r.static_detections_removed += further.static_detections_removed;
  r.frames_with_static_detections += further.frames_with_static_detections;
  r.frames_sweep_filter_restored += further.frames_sweep_filter_restored;
  r.texture_epipolar_matches += further.texture_epipolar_matches;
  r.albedo_edge_points += further.albedo_edge_points;
  r.off_colour_points += further.off_colour_points;
  r.frames_with_off_colour += further.frames_with_off_colour;
  r.clipped_samples += further.clipped_samples;
  r.clipping_samples_examined += further.clipping_samples_examined;
  r.frames_clipping_examined += further.frames_clipping_examined;
  r.frames_with_clipped_scene += further.frames_with_clipped_scene;
  r.features_clipped_samples += further.features_clipped_samples;
  r.features_clipping_samples_examined += further.features_clipping_samples_examined;
  r.frames_features_clipping_examined += further.frames_features_clipping_examined;
  r.frames_with_clipped_features += further.frames_with_clipped_features;
  r.triangulation_failures += further.triangulation_failures;
  r.grazing_points += further.grazing_points;
  r.seconds_detect += further.seconds_detect;
  r.seconds_triangulate += further.seconds_triangulate;
  r.laser_pose_inverse_fits = r.laser_pose_inverse_fits || further.laser_pose_inverse_fits;
  if (r.laser_on_inverted_at < 0) r.laser_on_inverted_at = further.laser_on_inverted_at;
  if (r.laser_seen_in.empty()) {
    r.laser_seen_in = further.laser_seen_in;
    r.laser_colour_warning = further.laser_colour_warning;
  }
  if (r.features_colour.empty()) r.features_colour = further.features_colour;
}

}  // namespace uwscan
