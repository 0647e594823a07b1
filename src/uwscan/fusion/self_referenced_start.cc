// The self-referenced scan's start (SelfReferencedPoseProvider): frames
// held until the laser's profiles span the scene's plane, the odometry
// started on their surface, the held frames tracked and placed again until
// their poses settle, and the start refused where that surface cannot be
// the scene's. Members of SelfReferencedPoseProvider (self_referenced.h).
#include <Eigen/Geometry>
#include <cmath>

#include "uwscan/fusion/self_referenced.h"
#include "uwscan/util/error.h"
#include "uwscan/util/statistics.h"

namespace uwscan::fusion {

bool SelfReferencedPoseProvider::StartPlaneFacesCamera(const SurfaceModel& surface) const {
  if (!options_.surface.extrapolate_plane) return true;
  const std::optional<double> cosine = surface.DominantPlaneViewCosine();
  return cosine && *cosine >= options_.min_start_plane_view_cosine;
}

void SelfReferencedPoseProvider::RefuseStart() {
  ++init_refused_;
  odometry_.reset();
  surface_.reset();
  init_surface_.reset();  // rebuilt from the held frames at the next attempt
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
  // frames between are placed between the tracked ones around them. After
  // an attempt refused because its tracked profiles were too narrow for the
  // plane, the first tracking (a screen: do they span it now?) takes every
  // start_screen_every-th only. (Not after a refusal for poses that would
  // not settle: there the question is the poses.)
  const size_t every = static_cast<size_t>(options_.track_every);
  const size_t screen_every = static_cast<size_t>(
      options_.start_screen_every > 0 ? options_.start_screen_every : options_.track_every);
  std::vector<std::optional<Rigid3d>> previous_poses;
  std::vector<double> moved_m;  // each refinement's change after the first
  bool converging = true;
  for (int refinement = 0; refinement < max_refinements && held_.size() > 2; ++refinement) {
    if (refinement >= min_refinements && (init_settled_ || !converging)) break;
    size_t last_tracked = 0;
    const size_t stride = init_refused_narrow_ > 0 && refinement == 0 ? screen_every : every;
    for (size_t i = 1; i < held_.size(); ++i) {
      if (i % stride != 0 && i + 1 < held_.size()) continue;
      Held& h = held_[i];
      const vo::FrameResult result =
          odometry_->ProcessFrame(h.input.image, h.mask, h.input.timestamp_s);
      CountBundleAdjustment(result, /*at_start=*/true);
      ++init_frames_tracked_;
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
      ++init_refused_narrow_;
      RefuseStart();
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
    RefuseStart();
    return {};
  }
  // Refinements that began to diverge: wait for more frames, a few times
  // (max_unsettled_start_refusals; after the plane's check, whose refusals
  // do not count).
  if (!init_settled_ && !converging &&
      init_refused_unsettled_ < options_.max_unsettled_start_refusals) {
    ++init_refused_unsettled_;
    RefuseStart();
    return {};
  }
  running_ = true;
  odometry_->SetBundleAdjustmentIterations(options_.running_ba_iterations);
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
    return vo::SurfaceHit{hit->point, hit->sigma_m, hit->extrapolated, hit->provisional};
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

}  // namespace uwscan::fusion
