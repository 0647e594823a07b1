#include "uwscan/fusion/self_referenced.h"

#include <Eigen/Geometry>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <unordered_map>

#include "uwscan/util/error.h"
#include "uwscan/util/statistics.h"

namespace uwscan::fusion {

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
  UWS_CHECK(init_refinements >= 0 && max_init_refinements >= init_refinements, context,
            "init refinements must be >= 0 and at most the maximum, got ", init_refinements,
            " and ", max_init_refinements);
  UWS_CHECK(init_settled_m > 0 && init_settled_deg > 0, context,
            "the settled start's tolerances must be > 0");
  UWS_CHECK(min_start_plane_view_cosine >= 0 && min_start_plane_view_cosine <= 1, context,
            "the start plane's view cosine must be in [0, 1], got ", min_start_plane_view_cosine);
  UWS_CHECK(init_converging_ratio > 0 && init_converging_ratio <= 1, context,
            "the start's converging ratio must be in (0, 1], got ", init_converging_ratio);
  UWS_CHECK(track_every >= 1, context, "track every N frames needs N >= 1, got ", track_every);
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

PreparedFrame SelfReferencedPoseProvider::MakePrepared(const cv::Mat& raw, const cv::Mat* line_mask,
                                                       const std::optional<cv::Point>& bayer_offset,
                                                       const Camera& tracking) const {
  PreparedFrame prepared;
  prepared.variant = PreparedVariant(bayer_offset);
  const cv::Size tracked(tracking.width, tracking.height);
  prepared.image = NormalizeIllumination(
      TrackedPassiveImage(raw, camera_.bayer, laser_channel_, bayer_offset, tracked),
      options_.illumination_sigma_fraction * tracking.width,
      options_.contrast_sigma_fraction * tracking.width);
  if (line_mask) {
    prepared.has_mask = true;
    prepared.mask = TrackedLineMask(*line_mask, tracked);
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
  const int next = next_tracked_index_.load(std::memory_order_relaxed);
  const int every = options_.track_every;
  if (every > 1 && next >= 0 && ((frame.index - next) % every + every) % every != 0) return {};
  return MakePrepared(frame.image, frame.detection ? &frame.detection->mask : nullptr,
                      ChooseBayerOffset(frame.image), TrackedCamera(frame.image));
}

Camera SelfReferencedPoseProvider::TrackedCamera(const cv::Mat& frame) const {
  return TrackingCamera(camera_, tracking_halvings_, ChooseBayerOffset(frame));
}

SelfReferencedPoseProvider::Held SelfReferencedPoseProvider::Prepare(
    const FrameInput& frame, const cv::Mat& line_mask) const {
  Held held;
  held.input = frame;
  held.input.detection = nullptr;
  held.input.profile = nullptr;
  held.input.prepared = nullptr;
  const PreparedFrame* ahead = frame.prepared;
  if (ahead && !ahead->image.empty() && ahead->variant == PreparedVariant(bayer_offset_)) {
    held.input.image = ahead->image;
    held.mask = ahead->has_mask
                    ? ahead->mask
                    : TrackedLineMask(line_mask, {tracking_camera_.width, tracking_camera_.height});
  } else {
    PreparedFrame prepared = MakePrepared(frame.image, &line_mask, bayer_offset_, tracking_camera_);
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
    next_tracked_index_.store(-1, std::memory_order_relaxed);
  } else if (skipped_.empty()) {
    next_tracked_index_.store(frame.index + options_.track_every, std::memory_order_relaxed);
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
  Held held = Prepare(frame, line_mask);
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

bool SelfReferencedPoseProvider::StartPlaneFacesCamera(const SurfaceModel& surface) const {
  if (!options_.surface.extrapolate_plane) return true;
  const std::optional<double> cosine = surface.DominantPlaneViewCosine();
  return cosine && *cosine >= options_.min_start_plane_view_cosine;
}

std::vector<PoseUpdate> SelfReferencedPoseProvider::TryInitialize() {
  // The held frames' profiles, placed with the first held frame's pose (or
  // where an earlier attempt tracked them): the platform moves while they
  // are taken. After a loss the map restarts at the last known pose.
  const Rigid3d origin = last_pose_.value_or(Rigid3d());
  // A later pass starts where the first did, on the pass before's surface.
  const bool use_prior = options_.prior_surface && !last_pose_;
  if (use_prior && !init_surface_) {
    while (!held_.empty() && held_.front().input.index < options_.prior_first_frame) {
      held_.pop_front();  // no pose in the first pass either
      ++dropped_;
    }
    if (held_.empty()) return {};
    init_surface_ = std::make_shared<SurfaceModel>(*options_.prior_surface);
    init_surface_frames_ = held_.size();  // their profiles are in it already
  }
  // The surface of the held frames grows with them (one AddProfile per
  // frame, not all held frames again at every attempt); it is built anew
  // only when the oldest held frame was dropped.
  if (!init_surface_) {
    init_surface_ = std::make_shared<SurfaceModel>(camera_, origin, options_.surface);
    init_surface_frames_ = 0;
  }
  // Frames tracked in an earlier attempt are placed where that put them,
  // later ones where the last of those was.
  for (size_t i = init_surface_frames_; i < held_.size(); ++i) {
    init_surface_->AddProfile(PoseGuess(i, origin), held_[i].profile);
  }
  init_surface_frames_ = held_.size();
  // Features only along the swept band would leave the pose's rotation
  // about the band undetermined: wait until the laser points define the
  // scene's plane, which gives every feature a depth.
  if (options_.surface.extrapolate_plane && !init_surface_->HasDominantPlane()) return {};
  surface_ = std::move(init_surface_);
  if (!StartOdometry(origin)) {
    init_surface_ = std::move(surface_);  // the held frames' surface, for the next attempt
    return {};
  }
  // The held frames' profiles were placed with the first frame's pose while
  // the platform moved (centimetres over a slow sweep): their surface is
  // bent and tilted, and so are the depths of the features it gives, and
  // the motion can make the swept band look wider than it is. Track the held
  // frames on it, place their profiles with those poses, and start again
  // from that surface; if it is too narrow for the scene's plane after all,
  // wait for more frames.
  // (A later pass starts on a surface placed with tracked poses already.)
  const int min_refinements = use_prior ? 0 : options_.init_refinements;
  const int max_refinements = min_refinements == 0 ? 0 : options_.max_init_refinements;
  init_refinements_done_ = 0;
  init_settled_ = false;
  init_last_change_.reset();
  // Every track_every-th held frame is tracked here, as once running; the
  // frames between are placed between the tracked ones around them.
  const size_t every = static_cast<size_t>(options_.track_every);
  std::vector<std::optional<Rigid3d>> previous_poses;
  std::vector<double> moved_m;  // each refinement's change after the first
  bool converging = true;
  for (int refinement = 0; refinement < max_refinements && held_.size() > 2; ++refinement) {
    if (refinement >= min_refinements && (init_settled_ || !converging)) break;
    size_t last_tracked = 0;
    for (size_t i = 1; i < held_.size(); ++i) {
      if (i % every != 0 && i + 1 < held_.size()) continue;
      Held& h = held_[i];
      const vo::FrameResult result =
          odometry_->ProcessFrame(h.input.image, h.mask, h.input.timestamp_s);
      CountBundleAdjustment(result, /*at_start=*/true);
      if (!result.world_from_camera) break;
      const Held& before = held_[last_tracked];
      const std::vector<StampedPose> ends = {
          {before.input.timestamp_s, last_tracked == 0 ? origin : *before.pose_guess},
          {h.input.timestamp_s, *result.world_from_camera}};
      for (size_t j = last_tracked + 1; j < i; ++j) {
        if (const auto pose = InterpolatePose(ends, held_[j].input.timestamp_s, 0.0)) {
          held_[j].pose_guess = *pose;
          surface_->AddProfile(*pose, held_[j].profile);
        }
      }
      h.pose_guess = *result.world_from_camera;
      surface_->AddProfile(*h.pose_guess, h.profile);
      last_tracked = i;
    }
    auto refined = std::make_shared<SurfaceModel>(camera_, origin, options_.surface);
    for (size_t i = 0; i < held_.size(); ++i)
      refined->AddProfile(PoseGuess(i, origin), held_[i].profile);
    if (options_.surface.extrapolate_plane && !refined->HasDominantPlane()) {
      ++init_refused_;
      odometry_.reset();
      surface_.reset();
      init_surface_.reset();  // rebuilt from the held frames at the next attempt
      return {};
    }
    std::vector<std::optional<Rigid3d>> poses;
    for (const Held& h : held_) poses.push_back(h.pose_guess);
    const std::optional<PoseChange> change =
        refinement > 0 ? RmsPoseChange(previous_poses, poses) : std::nullopt;
    if (change) {
      init_last_change_ = change;
      moved_m.push_back(change->moved_m);
    }
    init_settled_ = change && change->moved_m < options_.init_settled_m &&
                    change->turned_deg < options_.init_settled_deg;
    // Held frames the odometry cannot place better (a few frames of a
    // fast sweep) change as much every time: more would only shuffle them.
    converging =
        refinement < 2 || (change && StartConverging(moved_m, options_.init_converging_ratio));
    previous_poses = std::move(poses);
    ++init_refinements_done_;
    surface_ = std::move(refined);
    if (!StartOdometry(origin)) {
      surface_.reset();
      init_surface_.reset();
      return {};
    }
  }
  // Settled, but on a plane that runs through the camera: wait for more
  // frames. (Checked here, not at each attempt and refinement: there it
  // would refuse attempts that the refinements refuse anyway, and change
  // where the tank's 144 Hz starts begin.)
  if (!use_prior && !StartPlaneFacesCamera(*surface_)) {
    ++init_refused_;
    odometry_.reset();
    surface_.reset();
    init_surface_.reset();
    return {};
  }
  running_ = true;
  guess_odometry_.reset();
  const Held& first = held_.front();
  last_time_s_ = first.input.timestamp_s;
  if (init_frame_ < 0) init_frame_ = first.input.index;
  if (last_pose_) ++reinitialisations_;
  ++tracked_;
  ++keyframes_;
  last_pose_ = origin;
  std::vector<PoseUpdate> updates;
  Emit(PoseUpdate{first.input.index, origin}, first.input.timestamp_s, &updates);
  std::deque<Held> rest;
  rest.swap(held_);
  rest.pop_front();
  for (size_t k = 0; k < rest.size(); ++k) {
    const Held& h = rest[k];
    if (!running_) {
      held_.push_back(h);  // lost again: hold for the next initialisation
      continue;
    }
    if ((k + 1) % every != 0 && k + 1 < rest.size()) {
      skipped_.push_back(Skipped{h.input, h.mask, h.profile});  // placed after the next
      continue;
    }
    const auto tracked = TrackAfterSkipped(h);
    updates.insert(updates.end(), tracked.begin(), tracked.end());
  }
  return updates;
}

void SelfReferencedPoseProvider::GuessHeldMotion(Held* held) {
  if (!options_.guess_held_motion || guess_failed_) return;
  if (!guess_odometry_) {
    if (held->profile.points.size() < 10) return;  // no range for the scale prior yet
    std::vector<double> ranges;
    for (const auto& p : held->profile.points) ranges.push_back(p.point_in_camera.norm());
    vo::OdometryOptions options = options_.odometry;
    options.surface = nullptr;
    options.initial_median_depth_m = Median(std::move(ranges));
    guess_odometry_ = std::make_unique<vo::Odometry>(tracking_camera_, options);
    guess_frames_ = 0;
  }
  const vo::FrameResult result =
      guess_odometry_->ProcessFrame(held->input.image, held->mask, held->input.timestamp_s);
  held->guess_index = guess_frames_++;
  if (guess_odometry_->num_maps() > 1 ||
      (result.status != vo::FrameStatus::kInitializing && !result.world_from_camera)) {
    guess_odometry_.reset();  // lost: the guesses so far stand, no more
    guess_failed_ = true;
    return;
  }
  if (!result.world_from_camera) return;
  held->guess_world_from_camera = *result.world_from_camera;
  for (const auto& [index, pose] : result.earlier_poses) {
    for (Held& h : held_) {
      if (h.guess_index == index) h.guess_world_from_camera = pose;
    }
  }
  // Relative to the first held frame, which stands at the origin.
  const Held& first = held_.empty() ? *held : held_.front();
  if (!first.guess_world_from_camera) return;
  const Rigid3d origin = last_pose_.value_or(Rigid3d());
  const Rigid3d world_from_guess = origin * first.guess_world_from_camera->Inverse();
  bool placed_again = false;
  for (Held& h : held_) {
    if (h.guess_world_from_camera && !h.pose_guess) {
      h.pose_guess = world_from_guess * *h.guess_world_from_camera;
      placed_again = true;
    }
  }
  held->pose_guess = world_from_guess * *held->guess_world_from_camera;
  // Frames already in the held frames' surface were placed otherwise.
  if (placed_again) init_surface_.reset();
}

bool SelfReferencedPoseProvider::StartConverging(const std::vector<double>& moved_m, double ratio) {
  const size_t n = moved_m.size();
  return n < 3 || moved_m[n - 1] < ratio * moved_m[n - 2];
}

Rigid3d SelfReferencedPoseProvider::PoseGuess(size_t i, const Rigid3d& origin) const {
  for (size_t j = i + 1; j-- > 1;) {
    if (held_[j].pose_guess) return *held_[j].pose_guess;
  }
  return origin;
}

bool SelfReferencedPoseProvider::StartOdometry(const Rigid3d& origin) {
  vo::OdometryOptions odometry_options = options_.odometry;
  SurfaceModel* live = surface_.get();
  odometry_options.surface = [live](const Eigen::Vector3d& o,
                                    const Eigen::Vector3d& d) -> std::optional<vo::SurfaceHit> {
    const auto hit = live->Intersect(o, d);
    if (!hit) return std::nullopt;
    return vo::SurfaceHit{hit->point, hit->sigma_m, hit->extrapolated};
  };
  if (const auto oracle = options_.depth_oracle) {
    // The odometry's world is the first held frame's pose `origin`; the
    // truth's is the simulator's.
    const auto true_first = oracle->true_pose(held_.front().input.timestamp_s);
    UWS_CHECK(true_first.has_value(), "depth oracle: no true pose at ",
              held_.front().input.timestamp_s, " s");
    const Rigid3d truth_from_world = *true_first * origin.Inverse();
    const Rigid3d world_from_truth = truth_from_world.Inverse();
    const double sigma = options_.surface.local_sigma_m;
    odometry_options.surface = [oracle, truth_from_world, world_from_truth, sigma](
                                   const Eigen::Vector3d& o,
                                   const Eigen::Vector3d& d) -> std::optional<vo::SurfaceHit> {
      const auto hit = oracle->intersect(truth_from_world * o, truth_from_world.rotation * d);
      if (!hit) return std::nullopt;
      return vo::SurfaceHit{world_from_truth * *hit, sigma, false};
    };
  }
  if (options_.track_oracle) odometry_options.true_track_pixel = TrueTrackPixels();
  odometry_ = std::make_unique<vo::Odometry>(tracking_camera_, odometry_options);
  const Held& first = held_.front();
  const vo::FrameResult start = odometry_->InitializeFromSurface(first.input.image, first.mask,
                                                                 first.input.timestamp_s, origin);
  if (start.status == vo::FrameStatus::kTracked) return true;
  odometry_.reset();
  return false;
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
  const vo::FrameResult result = odometry_->ProcessFrame(frame.input.image, frame.mask,
                                                         frame.input.timestamp_s, {}, line_ranges);
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
    const double dt = std::max(frame.input.timestamp_s - last_time_s_, 1e-3);
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
  last_pose_ = pose;
  last_time_s_ = frame.input.timestamp_s;
  surface_->AddProfile(pose, frame.profile);
  return PoseUpdate{frame.input.index, pose};
}

std::vector<PoseUpdate> SelfReferencedPoseProvider::TrackAfterSkipped(const Held& frame) {
  const std::optional<Rigid3d> before = last_pose_;
  const double before_s = last_time_s_;
  std::vector<Skipped> skipped;
  skipped.swap(skipped_);
  const std::optional<PoseUpdate> raw = Track(frame);
  std::vector<PoseUpdate> updates;
  if (raw && before) {
    const std::vector<StampedPose> ends = {{before_s, *before},
                                           {frame.input.timestamp_s, raw->world_from_camera}};
    for (const Skipped& s : skipped) {
      const auto pose = InterpolatePose(ends, s.input.timestamp_s, 0.0);
      if (!pose) continue;
      surface_->AddProfile(*pose, s.profile);
      ++interpolated_;
      Emit(PoseUpdate{s.input.index, *pose}, s.input.timestamp_s, &updates);
    }
  }
  Emit(raw, frame.input.timestamp_s, &updates);
  return updates;
}

std::vector<PoseUpdate> SelfReferencedPoseProvider::Finish() {
  std::vector<PoseUpdate> updates;
  if (running_ && !skipped_.empty()) {
    // The last frames were not tracked: track the last of them.
    Skipped last = std::move(skipped_.back());
    skipped_.pop_back();
    last.input.profile = &last.profile;
    updates = TrackAfterSkipped(Prepare(last.input, last.line_mask));
  }
  skipped_.clear();
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
          {"lost", lost_},
          {"reinitialisations", reinitialisations_},
          {"frames_without_pose_at_start", dropped_},
          {"first_frame_with_pose", init_frame_},
          {"start_attempts_refused", init_refused_},
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
          {"bundle_adjustments_stopped_by_time_limit", bundle_adjustments_time_limited_},
          {"surface_points", surface_ ? surface_->size() : 0}};
}

}  // namespace uwscan::fusion
