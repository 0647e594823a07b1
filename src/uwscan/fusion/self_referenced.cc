#include "uwscan/fusion/self_referenced.h"

#include <opencv2/imgproc.hpp>

#include "uwscan/util/error.h"

namespace uwscan::fusion {

void SelfReferencedOptions::Check() const {
  odometry.Check();
  surface.Check();
  UWS_CHECK(mask_dilation_px >= 0 && max_init_frames >= 2 && init_attempt_every >= 1,
            "self-referenced odometry: invalid options");
}

cv::Mat SelfReferencedPoseProvider::PassiveImage(const cv::Mat& image, const std::string& bayer,
                                                 int laser_channel) {
  // Features in a colour the laser does not light: red unless the laser is red.
  const int passive_rgb = laser_channel == laser::kRed ? laser::kBlue : laser::kRed;
  cv::Mat bgr;
  if (image.channels() == 3) {
    bgr = image;
  } else if (bayer != "none") {
    // OpenCV names Bayer codes by the second row's pattern start.
    const int code = bayer == "rggb"   ? cv::COLOR_BayerBG2BGR
                     : bayer == "bggr" ? cv::COLOR_BayerRG2BGR
                     : bayer == "grbg" ? cv::COLOR_BayerGB2BGR
                                       : cv::COLOR_BayerGR2BGR;
    cv::cvtColor(image, bgr, code);
  } else {
    return image;
  }
  cv::Mat channel;
  cv::extractChannel(bgr, channel, 2 - passive_rgb);
  return channel;
}

SelfReferencedPoseProvider::SelfReferencedPoseProvider(const Camera& camera, int laser_channel,
                                                       const SelfReferencedOptions& options)
    : camera_(camera), laser_channel_(laser_channel), options_(options) {
  options_.Check();
}

std::vector<PoseUpdate> SelfReferencedPoseProvider::Add(const FrameInput& frame) {
  ++frames_;
  Held held;
  held.input = frame;
  held.input.image = PassiveImage(frame.image, camera_.bayer, laser_channel_);
  if (held.input.image.data == frame.image.data) held.input.image = frame.image.clone();
  held.input.detection = nullptr;
  held.input.profile = nullptr;
  if (frame.detection && !frame.detection->mask.empty()) {
    const int d = options_.mask_dilation_px;
    cv::dilate(frame.detection->mask, held.mask,
               cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * d + 1, 2 * d + 1)));
  }
  if (frame.profile) held.profile = *frame.profile;

  if (running_) {
    std::vector<PoseUpdate> updates;
    if (const auto update = Track(held)) updates.push_back(*update);
    return updates;
  }
  held_.push_back(std::move(held));
  if (static_cast<int>(held_.size()) % options_.init_attempt_every != 0 && held_.size() > 1) return {};
  auto updates = TryInitialize();
  if (!running_ && static_cast<int>(held_.size()) >= options_.max_init_frames) {
    held_.pop_front();  // never got a pose: the laser did not measure enough
    ++dropped_;
  }
  return updates;
}

std::vector<PoseUpdate> SelfReferencedPoseProvider::TryInitialize() {
  // The held frames' profiles, placed with the first held frame's pose: the
  // platform moves millimetres while they are taken (a hover; a moving
  // platform initialises from fewer frames). After a loss the map restarts
  // at the last known pose.
  const Rigid3d origin = last_pose_.value_or(Rigid3d());
  surface_ = std::make_unique<SurfaceModel>(camera_, origin, options_.surface);
  for (const auto& h : held_) surface_->AddProfile(origin, h.profile);
  vo::OdometryOptions odometry_options = options_.odometry;
  SurfaceModel* live = surface_.get();
  odometry_options.surface = [live](const Eigen::Vector3d& o,
                                    const Eigen::Vector3d& d) -> std::optional<vo::SurfaceHit> {
    const auto hit = live->Intersect(o, d);
    if (!hit) return std::nullopt;
    return vo::SurfaceHit{hit->point, hit->sigma_m};
  };
  odometry_ = std::make_unique<vo::Odometry>(camera_, odometry_options);
  const Held& first = held_.front();
  const vo::FrameResult start = odometry_->InitializeFromSurface(
      first.input.image, first.mask, first.input.timestamp_s, origin);
  if (start.status != vo::FrameStatus::kTracked) {
    odometry_.reset();
    surface_.reset();
    return {};
  }
  running_ = true;
  if (init_frame_ < 0) init_frame_ = first.input.index;
  if (last_pose_) ++reinitialisations_;
  ++tracked_;
  ++keyframes_;
  last_pose_ = origin;
  std::vector<PoseUpdate> updates = {{first.input.index, origin}};
  std::deque<Held> rest;
  rest.swap(held_);
  rest.pop_front();
  for (const auto& h : rest) {
    if (!running_) {
      held_.push_back(h);  // lost again: hold for the next initialisation
      continue;
    }
    if (const auto update = Track(h)) updates.push_back(*update);
  }
  return updates;
}

std::optional<PoseUpdate> SelfReferencedPoseProvider::Track(const Held& frame) {
  const vo::FrameResult result =
      odometry_->ProcessFrame(frame.input.image, frame.mask, frame.input.timestamp_s);
  if (result.keyframe) ++keyframes_;
  if (!result.world_from_camera) {
    ++lost_;
    // Start again from the surface at the next frames, at the last pose.
    running_ = false;
    odometry_.reset();
    surface_.reset();
    held_.clear();
    return std::nullopt;
  }
  ++tracked_;
  Rigid3d pose = *result.world_from_camera;
  if (options_.refine_with_profile) {
    const PoseRefinementResult refined =
        RefinePoseWithProfile(camera_, *odometry_, pose, frame.profile, *surface_, options_.refinement);
    if (refined.refined) {
      pose = refined.world_from_camera;
      ++refined_;
    }
  }
  last_pose_ = pose;
  surface_->AddProfile(pose, frame.profile);
  return PoseUpdate{frame.input.index, pose};
}

std::vector<PoseUpdate> SelfReferencedPoseProvider::Finish() {
  if (!running_ && !held_.empty()) {
    auto updates = TryInitialize();
    dropped_ += static_cast<int>(held_.size());
    held_.clear();
    return updates;
  }
  return {};
}

nlohmann::json SelfReferencedPoseProvider::Details() const {
  return {{"frames", frames_},
          {"tracked", tracked_},
          {"lost", lost_},
          {"reinitialisations", reinitialisations_},
          {"frames_without_pose_at_start", dropped_},
          {"first_frame_with_pose", init_frame_},
          {"keyframes", keyframes_},
          {"refined_with_profile", refined_},
          {"surface_points", surface_ ? surface_->size() : 0}};
}

}  // namespace uwscan::fusion
