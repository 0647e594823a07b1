#include "uwscan/fusion/self_referenced.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <iterator>
#include <opencv2/imgproc.hpp>
#include <unordered_map>

#include "uwscan/util/error.h"

namespace uwscan::fusion {

vo::OdometryOptions SelfReferencedOdometryOptions() {
  vo::OdometryOptions options;
  options.ba.huber_px = 0.3;
  return options;
}

void SelfReferencedOptions::Check() const {
  odometry.Check();
  surface.Check();
  line_ranges.Check();
  const std::string context = "self-referenced odometry: ";
  UWS_CHECK(mask_dilation_px >= 0, context, "mask dilation must be >= 0 px, got ",
            mask_dilation_px);
  UWS_CHECK(max_init_frames >= 2, context, "at least 2 frames must be held at the start, got ",
            max_init_frames);
  UWS_CHECK(init_attempt_every >= 1, context,
            "initialisation attempts must be at least 1 frame apart, got ", init_attempt_every);
  UWS_CHECK(max_tracking_width >= 0, context,
            "the tracking width must be >= 0 (0 = full resolution), got ", max_tracking_width);
  UWS_CHECK(contrast_sigma_fraction >= 0 && contrast_sigma_fraction <= 0.5, context,
            "the contrast scale must be in [0, 0.5] of the width, got ", contrast_sigma_fraction);
  UWS_CHECK(log_offset_fraction >= 0 && log_offset_fraction <= kMaxLogOffsetFraction, context,
            "the tracked image's log offset must be in [0, ", kMaxLogOffsetFraction,
            "] of its mean, got ", log_offset_fraction);
  UWS_CHECK(init_refinements >= 0 && max_init_refinements >= init_refinements, context,
            "init refinements must be >= 0 and at most the maximum, got ", init_refinements,
            " and ", max_init_refinements);
  UWS_CHECK(init_settled_m > 0 && init_settled_deg > 0, context,
            "the settled start's tolerances must be > 0");
  UWS_CHECK(min_start_plane_view_cosine >= 0 && min_start_plane_view_cosine <= 1, context,
            "the start plane's view cosine must be in [0, 1], got ", min_start_plane_view_cosine);
  UWS_CHECK(init_converging_ratio > 0 && init_converging_ratio <= 1, context,
            "the start's converging ratio must be in (0, 1], got ", init_converging_ratio);
  UWS_CHECK(running_ba_iterations >= 1, context,
            "the running scan's BA iterations must be >= 1, got ", running_ba_iterations);
  UWS_CHECK(track_every >= 1, context, "track every N frames needs N >= 1, got ", track_every);
  UWS_CHECK(start_screen_every >= 0, context,
            "the refused start's screen tracking every N needs N >= 1 (0: as once running), got ",
            start_screen_every);
  UWS_CHECK(!prior_surface || prior_first_frame >= 0, context,
            "a first pass's surface needs the frame its map started at");
}

SelfReferencedPoseProvider::SelfReferencedPoseProvider(const Camera& camera, int laser_channel,
                                                       const SelfReferencedOptions& options)
    : camera_(camera), laser_channel_(laser_channel), options_(options) {
  options_.Check();
  // Keyframes at the latest after the same time, not the same count of
  // tracked frames.
  int& keyframe_interval = options_.odometry.max_frames_between_keyframes;
  if (keyframe_interval > 0)
    keyframe_interval =
        std::max(1, (keyframe_interval + options_.track_every / 2) / options_.track_every);
  tracking_halvings_ = TrackingHalvings(camera_.width, options_.max_tracking_width);
  tracking_camera_ = TrackingCamera(camera_, tracking_halvings_, std::nullopt);
  smoother_ = std::make_unique<PoseSmoother>(options_.smoothing_half_window);
}

std::optional<cv::Point> SelfReferencedPoseProvider::ChooseBayerOffset(const cv::Mat& frame) const {
  if (tracking_halvings_ > 0 && frame.channels() == 1)
    return BayerSampleOffset(camera_.bayer, PassiveColour(laser_channel_));
  return std::nullopt;
}

// PreparedFrame::variant: which Bayer sample the image was made from.
static int PreparedVariant(const std::optional<cv::Point>& bayer_offset) {
  return bayer_offset ? 1 + bayer_offset->x + 2 * bayer_offset->y : 0;
}

void SelfReferencedPoseProvider::Emit(const std::optional<PoseUpdate>& raw, double timestamp_s,
                                      std::vector<PoseUpdate>* out) {
  if (raw) preliminary_.push_back(*raw);
  const auto final_poses = raw ? smoother_->Add(*raw, timestamp_s) : smoother_->Flush();
  out->insert(out->end(), final_poses.begin(), final_poses.end());
}

// The union of line masks (empty ones left out; empty if all are).
static cv::Mat MaskUnion(const std::vector<const cv::Mat*>& masks) {
  cv::Mat all;
  for (const cv::Mat* mask : masks) {
    if (mask->empty()) continue;
    if (all.empty()) {
      all = *mask;
    } else {
      UWS_CHECK(mask->size() == all.size(), "line masks of different sizes");
      all = all | *mask;
    }
  }
  return all;
}

PreparedFrame SelfReferencedPoseProvider::MakePrepared(
    const std::vector<cv::Mat>& raws, const std::vector<const cv::Mat*>& line_masks,
    const std::optional<cv::Point>& bayer_offset, const Camera& tracking) const {
  PreparedFrame prepared;
  prepared.variant = PreparedVariant(bayer_offset);
  prepared.averaged_frames = static_cast<int>(raws.size());
  const cv::Size tracked(tracking.width, tracking.height);
  prepared.image = NormalizeIllumination(
      TrackedPassiveImage(raws, camera_.bayer, laser_channel_, bayer_offset, tracked),
      options_.illumination_sigma_fraction * tracking.width,
      options_.contrast_sigma_fraction * tracking.width, options_.log_offset_fraction);
  if (std::all_of(line_masks.begin(), line_masks.end(), [](const cv::Mat* m) { return m; })) {
    prepared.has_mask = true;
    prepared.mask = TrackedLineMask(MaskUnion(line_masks), tracked);
  }
  return prepared;
}

cv::Mat SelfReferencedPoseProvider::TrackedLineMask(const cv::Mat& line_mask,
                                                    const cv::Size& tracked) const {
  if (line_mask.empty()) return {};
  const int d = options_.mask_dilation_px;
  cv::Mat dilated;
  cv::dilate(line_mask, dilated,
             cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * d + 1, 2 * d + 1)));
  return TrackedMask(dilated, tracked);
}

PreparedFrame SelfReferencedPoseProvider::PrepareAhead(const FrameInput& frame) const {
  UWS_CHECK(!frame.image.empty(), "frame ", frame.index, ": empty image");
  const int last = last_tracked_index_.load(std::memory_order_relaxed);
  const int every = options_.track_every;
  const cv::Mat* line_mask = frame.detection ? &frame.detection->mask : nullptr;
  ahead_seen_.push_back(frame.index);
  if (ahead_seen_.size() > kAheadSeen) ahead_seen_.pop_front();
  // The frames given since the last tracked one, this one included (Add
  // tracks every track_every-th it is given): counted where the last
  // tracked one is still among those remembered, else by index.
  int since = frame.index - last;
  if (last >= 0 && ahead_seen_.front() <= last) {
    since = static_cast<int>(
        std::count_if(ahead_seen_.begin(), ahead_seen_.end(), [&](int i) { return i > last; }));
  }
  // Held frames are tracked one by one; the frames kept for a mean are
  // those since the last one prepared for tracking.
  if (!Averaging() || last < 0) ahead_frames_.clear();
  if (every > 1 && last >= 0 && (since % every + every) % every != 0) {
    if (Averaging()) {
      if (static_cast<int>(ahead_frames_.size()) + 1 >= every)
        ahead_frames_.erase(ahead_frames_.begin());
      ahead_frames_.push_back(
          {frame.index, frame.image, line_mask ? *line_mask : cv::Mat(), line_mask != nullptr});
    }
    return {};
  }
  std::vector<cv::Mat> raws;
  std::vector<const cv::Mat*> masks;
  for (const AheadFrame& a : ahead_frames_) {
    raws.push_back(a.image);
    masks.push_back(a.has_mask ? &a.line_mask : nullptr);
  }
  raws.push_back(frame.image);
  masks.push_back(line_mask);
  PreparedFrame prepared =
      MakePrepared(raws, masks, ChooseBayerOffset(frame.image), TrackedCamera(frame.image));
  prepared.first_averaged = ahead_frames_.empty() ? frame.index : ahead_frames_.front().index;
  ahead_frames_.clear();
  return prepared;
}

Camera SelfReferencedPoseProvider::TrackedCamera(const cv::Mat& frame) const {
  return TrackingCamera(camera_, tracking_halvings_, ChooseBayerOffset(frame));
}

SelfReferencedPoseProvider::Held SelfReferencedPoseProvider::Prepare(const FrameInput& frame,
                                                                     const cv::Mat& line_mask,
                                                                     bool with_skipped) const {
  Held held;
  held.input = frame;
  held.input.detection = nullptr;
  held.input.profile = nullptr;
  held.input.prepared = nullptr;
  std::vector<cv::Mat> raws;
  std::vector<const cv::Mat*> masks;
  double time_sum = 0.0;
  if (with_skipped) {
    for (const Skipped& s : skipped_) {
      raws.push_back(s.input.image);
      masks.push_back(&s.line_mask);
      time_sum += s.input.timestamp_s;
    }
  }
  const int first = raws.empty() ? frame.index : skipped_.front().input.index;
  raws.push_back(frame.image);
  masks.push_back(&line_mask);
  if (raws.size() > 1) held.averaged_time_s = (time_sum + frame.timestamp_s) / raws.size();
  const PreparedFrame* ahead = frame.prepared;
  if (ahead && !ahead->image.empty() && ahead->variant == PreparedVariant(bayer_offset_) &&
      ahead->averaged_frames == static_cast<int>(raws.size()) && ahead->first_averaged == first) {
    held.input.image = ahead->image;
    held.mask =
        ahead->has_mask
            ? ahead->mask
            : TrackedLineMask(MaskUnion(masks), {tracking_camera_.width, tracking_camera_.height});
  } else {
    // Not made ahead (the reading thread guessed another frame to track).
    ++prepared_late_;
    PreparedFrame prepared = MakePrepared(raws, masks, bayer_offset_, tracking_camera_);
    held.input.image = std::move(prepared.image);
    held.mask = std::move(prepared.mask);
  }
  if (frame.profile) held.profile = *frame.profile;
  return held;
}

std::vector<PoseUpdate> SelfReferencedPoseProvider::Add(const FrameInput& frame) {
  std::vector<PoseUpdate> updates = AddFrame(frame);
  // Running with no frame skipped since: this one was tracked.
  if (!running_) {
    last_tracked_index_.store(-1, std::memory_order_relaxed);
  } else if (skipped_.empty()) {
    last_tracked_index_.store(frame.index, std::memory_order_relaxed);
  }
  return updates;
}

std::vector<PoseUpdate> SelfReferencedPoseProvider::AddFrame(const FrameInput& frame) {
  preliminary_.clear();
  if (frames_ == 0) {
    bayer_offset_ = ChooseBayerOffset(frame.image);
    if (bayer_offset_)
      tracking_camera_ = TrackingCamera(camera_, tracking_halvings_, bayer_offset_);
  }
  ++frames_;
  UWS_CHECK(!bayer_offset_ || frame.image.channels() == 1, "frame ", frame.index,
            ": a colour image in a sequence of raw Bayer frames");
  const cv::Mat no_mask;
  const cv::Mat& line_mask = frame.detection ? frame.detection->mask : no_mask;
  if (running_ && static_cast<int>(skipped_.size()) + 1 < options_.track_every) {
    Skipped skipped{frame, line_mask, frame.profile ? *frame.profile : laser::Profile{}};
    skipped.input.detection = nullptr;
    skipped.input.profile = nullptr;
    skipped.input.prepared = nullptr;
    skipped_.push_back(std::move(skipped));
    return {};
  }
  Held held = Prepare(frame, line_mask, running_ && Averaging());
  if (running_) return TrackAfterSkipped(held);
  // Every track_every-th held frame, as once running (the others take the
  // guess of the frame before, PoseGuess).
  if (held_.size() % options_.track_every == 0) GuessHeldMotion(&held);
  held_.push_back(std::move(held));
  if (static_cast<int>(held_.size()) % options_.init_attempt_every != 0 && held_.size() > 1)
    return {};
  auto updates = TryInitialize();
  if (!running_ && static_cast<int>(held_.size()) >= options_.max_init_frames) {
    held_.pop_front();  // never got a pose: the laser did not measure enough
    // The new first held frame is at the origin now: tracked poses follow.
    if (held_.front().pose_guess) {
      const Rigid3d origin = last_pose_.value_or(Rigid3d());
      const Rigid3d shift = origin * held_.front().pose_guess->Inverse();
      for (Held& h : held_) {
        if (h.pose_guess) h.pose_guess = shift * *h.pose_guess;
      }
    }
    held_.front().pose_guess.reset();
    init_surface_.reset();
    ++dropped_;
  }
  return updates;
}

std::function<std::optional<Eigen::Vector2d>(const vo::FeatureTrack&, double)>
SelfReferencedPoseProvider::TrueTrackPixels() const {
  // The scene point of each track: where its pixel's ray meets the true
  // scene at the first time it is asked for (the frame it was detected in),
  // from the true pose then; none if the ray misses the scene.
  auto points = std::make_shared<std::unordered_map<uint64_t, std::optional<Eigen::Vector3d>>>();
  return [truth = options_.track_oracle, camera = tracking_camera_, points](
             const vo::FeatureTrack& track, double timestamp_s) -> std::optional<Eigen::Vector2d> {
    const auto world_from_camera = truth->true_pose(timestamp_s);
    if (!world_from_camera) return std::nullopt;
    auto [it, first] = points->try_emplace(track.id);
    if (first) {
      const auto ray = camera.BackProject(track.pixel);
      if (ray) {
        it->second = truth->intersect(*world_from_camera * ray->origin,
                                      world_from_camera->rotation * ray->direction);
      }
      return std::nullopt;
    }
    if (!it->second) return std::nullopt;
    return camera.Project(world_from_camera->Inverse() * *it->second);
  };
}

void SelfReferencedPoseProvider::Restart() {
  // Start again from the surface at the next frames, at the last pose.
  ++lost_;
  running_ = false;
  pending_.clear();
  odometry_.reset();
  surface_.reset();
  init_surface_.reset();
  held_.clear();
  guess_odometry_.reset();
  guess_failed_ = false;
}

void SelfReferencedPoseProvider::CountBundleAdjustment(const vo::FrameResult& result,
                                                       bool at_start) {
  const bool ran = result.bundle_adjustment.keyframes > 0;
  bundle_adjustments_ += ran;
  init_bundle_adjustments_ += at_start && ran;
  bundle_adjustments_time_limited_ += result.bundle_adjustment.time_limited;
}

std::optional<PoseUpdate> SelfReferencedPoseProvider::Track(const Held& frame) {
  vo::Odometry::LineRanges line_ranges;
  if (options_.use_line_ranges && !frame.profile.points.empty()) {
    line_ranges = [this, &frame](const Rigid3d& camera_from_world) {
      return LineRangeConstraints(tracking_camera_, odometry_->map(), camera_from_world,
                                  frame.profile, options_.line_ranges);
    };
  }
  const double time_s = frame.averaged_time_s.value_or(frame.input.timestamp_s);
  const vo::FrameResult result =
      odometry_->ProcessFrame(frame.input.image, frame.mask, time_s, {}, line_ranges);
  if (result.keyframe) ++keyframes_;
  line_ranges_ += result.line_ranges;
  CountBundleAdjustment(result, /*at_start=*/false);
  tracks_cut_by_line_ += result.tracking.lost_mask;
  tracks_reacquired_ += result.tracking.reacquired;
  if (!result.world_from_camera) {
    Restart();
    return std::nullopt;
  }
  const Rigid3d pose = *result.world_from_camera;
  if (last_pose_) {
    const double dt = std::max(time_s - last_time_s_, 1e-3);
    const double rotation_deg =
        Eigen::AngleAxisd(pose.rotation * last_pose_->rotation.conjugate()).angle() * 180.0 / M_PI;
    const double distance = (pose.translation - last_pose_->translation).norm();
    if (rotation_deg > options_.max_rotation_rate_deg_s * dt ||
        distance > options_.max_speed_m_s * dt) {
      ++implausible_;
      Restart();
      return std::nullopt;
    }
  }
  ++tracked_;
  averaged_ += frame.averaged_time_s.has_value();
  last_pose_ = pose;
  last_time_s_ = time_s;
  // An averaged image's pose is that of its mean time, not of the frame.
  if (!frame.averaged_time_s) surface_->AddProfile(pose, frame.profile);
  return PoseUpdate{frame.input.index, pose};
}

std::vector<PoseUpdate> SelfReferencedPoseProvider::TrackAfterSkipped(const Held& frame) {
  const std::optional<Rigid3d> before = last_pose_;
  const double before_s = last_time_s_;
  std::vector<Skipped> skipped;
  skipped.swap(skipped_);
  const std::optional<PoseUpdate> raw = Track(frame);
  std::vector<PoseUpdate> updates;
  if (frame.averaged_time_s) {
    // No frame was taken at the tracked time: each is placed between the
    // two tracked poses around it, those after this one's time later.
    std::vector<Skipped> frames;
    frames.swap(pending_);
    for (Skipped& s : skipped) frames.push_back({s.input, {}, std::move(s.profile)});
    frames.push_back({frame.input, {}, frame.profile});
    if (!raw) {
      Emit(std::nullopt, 0.0, &updates);  // lost: none of them gets a pose
      return updates;
    }
    std::vector<StampedPose> ends;
    if (before) ends.push_back({before_s, *before});
    ends.push_back({*frame.averaged_time_s, raw->world_from_camera});
    for (Skipped& f : frames) {
      f.input.image = cv::Mat();
      if (f.input.timestamp_s > *frame.averaged_time_s) {
        pending_.push_back(std::move(f));
        continue;
      }
      const auto pose = InterpolatePose(ends, f.input.timestamp_s, kMaxPendingS);
      if (pose) PlaceBetween(f, *pose, &updates);
    }
    return updates;
  }
  // Tracked alone after averaged images (the last frame of a sequence):
  // the frames still waiting for a later pose are placed first.
  skipped.insert(skipped.begin(), std::make_move_iterator(pending_.begin()),
                 std::make_move_iterator(pending_.end()));
  pending_.clear();
  if (raw && before) {
    const std::vector<StampedPose> ends = {{before_s, *before},
                                           {frame.input.timestamp_s, raw->world_from_camera}};
    for (const Skipped& s : skipped) {
      const auto pose = InterpolatePose(ends, s.input.timestamp_s, 0.0);
      if (pose) PlaceBetween(s, *pose, &updates);
    }
  }
  Emit(raw, frame.input.timestamp_s, &updates);
  return updates;
}

void SelfReferencedPoseProvider::PlaceBetween(const Skipped& frame, const Rigid3d& pose,
                                              std::vector<PoseUpdate>* updates) {
  surface_->AddProfile(pose, frame.profile);
  ++interpolated_;
  Emit(PoseUpdate{frame.input.index, pose}, frame.input.timestamp_s, updates);
}

std::vector<PoseUpdate> SelfReferencedPoseProvider::PlacePending() {
  // After the last tracked time: at the last pose (at most half the
  // frames of a mean later than it).
  std::vector<PoseUpdate> updates;
  for (const Skipped& f : pending_) {
    if (last_pose_ && f.input.timestamp_s - last_time_s_ <= kMaxPendingS)
      PlaceBetween(f, *last_pose_, &updates);
  }
  pending_.clear();
  return updates;
}

std::vector<PoseUpdate> SelfReferencedPoseProvider::Finish() {
  std::vector<PoseUpdate> updates;
  if (running_ && !skipped_.empty()) {
    // The last frames were not tracked: track the last of them (the mean
    // of them all when averaging).
    Skipped last = std::move(skipped_.back());
    skipped_.pop_back();
    last.input.profile = &last.profile;
    updates = TrackAfterSkipped(Prepare(last.input, last.line_mask, Averaging()));
  }
  skipped_.clear();
  if (running_ && !pending_.empty()) {
    const auto placed = PlacePending();
    updates.insert(updates.end(), placed.begin(), placed.end());
  }
  pending_.clear();
  if (!running_ && !held_.empty()) {
    const auto initialised = TryInitialize();
    updates.insert(updates.end(), initialised.begin(), initialised.end());
    dropped_ += static_cast<int>(held_.size());
    held_.clear();
  }
  Emit(std::nullopt, 0.0, &updates);
  return updates;
}

nlohmann::json SelfReferencedPoseProvider::Details() const {
  return {{"frames", frames_},
          {"tracked_image_width", tracking_camera_.width},
          {"tracked", tracked_},
          {"interpolated_between_tracked", interpolated_},
          {"tracked_images_averaged", averaged_},
          {"tracked_images_made_late", prepared_late_},
          {"lost", lost_},
          {"reinitialisations", reinitialisations_},
          {"frames_without_pose_at_start", dropped_},
          {"first_frame_with_pose", init_frame_},
          {"start_attempts_refused", init_refused_},
          {"start_attempts_refused_unsettled", init_refused_unsettled_},
          {"start_refinements", init_refinements_done_},
          {"start_settled",
           init_refinements_done_ > 1 ? nlohmann::json(init_settled_) : nlohmann::json()},
          {"start_last_change_mm",
           init_last_change_ ? nlohmann::json(1e3 * init_last_change_->moved_m) : nlohmann::json()},
          {"start_settled_within_mm", 1e3 * options_.init_settled_m},
          {"start_last_change_deg",
           init_last_change_ ? nlohmann::json(init_last_change_->turned_deg) : nlohmann::json()},
          {"start_settled_within_deg", options_.init_settled_deg},
          {"keyframes", keyframes_},
          {"implausible_poses_rejected", implausible_},
          {"tracks_cut_by_laser_line", tracks_cut_by_line_},
          {"tracks_reacquired", tracks_reacquired_},
          {"line_range_constraints", line_ranges_},
          {"bundle_adjustments", bundle_adjustments_},
          {"start_bundle_adjustments", init_bundle_adjustments_},
          {"start_frames_tracked", init_frames_tracked_},
          {"bundle_adjustments_stopped_by_time_limit", bundle_adjustments_time_limited_},
          {"surface_points", surface_ ? surface_->size() : 0},
          {"points_placed_again_on_settled_plane",
           odometry_ ? odometry_->provisional_points_placed_again() : 0}};
}

}  // namespace uwscan::fusion
