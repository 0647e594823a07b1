#include "uwscan/vo/odometry.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <unordered_set>

#include "uwscan/sensor/triangulation.h"
#include "uwscan/util/error.h"
#include "uwscan/util/statistics.h"
#include "uwscan/util/stopwatch.h"
#include "uwscan/vo/cost_functions.h"

namespace uwscan::vo {
namespace {

double ThreadCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

}  // namespace

const char* FrameStatusName(FrameStatus status) {
  switch (status) {
    case FrameStatus::kInitializing:
      return "initializing";
    case FrameStatus::kTracked:
      return "tracked";
    case FrameStatus::kLost:
      return "lost";
    case FrameStatus::kReinitialized:
      return "reinitialized";
    case FrameStatus::kInvalid:
      return "invalid";
  }
  return "?";
}

void OdometryOptions::Check() const {
  tracker.Check();
  ba.Check();
  UWS_CHECK(ransac_threshold_px > 0, "ransac_threshold_px must be > 0");
  UWS_CHECK(pnp_max_iterations >= 1, "pnp_max_iterations must be >= 1");
  UWS_CHECK(min_init_matches >= 8, "min_init_matches must be >= 8");
  UWS_CHECK(init_parallax_fraction > 0 && keyframe_parallax_fraction > 0,
            "parallax fractions must be > 0");
  UWS_CHECK(max_frames_between_keyframes >= 0, "max_frames_between_keyframes must be >= 0");
  UWS_CHECK(keyframe_min_tracked_ratio >= 0 && keyframe_min_tracked_ratio < 1,
            "keyframe_min_tracked_ratio must be in [0, 1)");
  UWS_CHECK(max_init_frames >= 2, "max_init_frames must be >= 2");
  UWS_CHECK(min_pnp_inliers >= 4, "min_pnp_inliers must be >= 4");
  UWS_CHECK(max_extrapolated_disagreement_px >= 0 && min_map_points_to_defer >= 0,
            "extrapolated-depth check settings must be >= 0");
  UWS_CHECK(max_refine_points >= 6, "max_refine_points must be >= 6");
  UWS_CHECK(min_triangulation_angle_deg > 0, "min_triangulation_angle_deg must be > 0");
  UWS_CHECK(max_reprojection_px > 0, "max_reprojection_px must be > 0");
  UWS_CHECK(max_step_depth_ratio > 0, "max_step_depth_ratio must be > 0");
  UWS_CHECK(initial_median_depth_m > 0, "initial_median_depth_m must be > 0");
  UWS_CHECK(async_merge_frames >= 1, "async_merge_frames must be >= 1");
}

cv::Mat ToGray8(const cv::Mat& image) {
  cv::Mat gray;
  if (image.empty()) return gray;
  cv::Mat channel = image;
  if (image.channels() == 3 || image.channels() == 4) {
    cv::extractChannel(image, channel, 1);  // green: the laser channel is masked anyway
  } else if (image.channels() != 1) {
    return gray;
  }
  if (channel.depth() == CV_8U) return channel;
  if (channel.depth() == CV_16U) {
    // 10/12/14-bit data is stored in 16 bits: scale by the bit depth the
    // frame uses (next power of two above its maximum), not by 1/256.
    double max_value = 0;
    cv::minMaxLoc(channel, nullptr, &max_value);
    double full_scale = 256.0;
    while (full_scale <= max_value && full_scale < 65536.0) full_scale *= 2.0;
    channel.convertTo(gray, CV_8U, 256.0 / full_scale);
    return gray;
  }
  return gray;
}

Odometry::Odometry(const Camera& camera, const OdometryOptions& options)
    : camera_(camera), options_(options), tracker_(options.tracker) {
  options_.Check();
  camera_.Check("vo camera");
}

void Odometry::SetBundleAdjustmentIterations(int iterations) {
  UWS_CHECK(iterations >= 1, "BA iterations must be >= 1, got ", iterations);
  options_.ba.max_iterations = iterations;
}

Odometry::~Odometry() { DiscardBundleAdjustment(); }

FrameResult Odometry::ProcessFrame(const cv::Mat& image, const cv::Mat& mask, double timestamp_s,
                                   const std::vector<RangeConstraint>& ranges,
                                   const LineRanges& line_ranges) {
  const auto start = std::chrono::steady_clock::now();
  const double cpu_start = ThreadCpuSeconds();
  FrameResult result;
  result.frame_index = frame_count_++;
  result.timestamp_s = timestamp_s;
  const cv::Mat gray = ToGray8(image);
  if (gray.empty() || gray.cols != camera_.width || gray.rows != camera_.height) {
    result.status = FrameStatus::kInvalid;
    result.message = image.empty()  ? "empty image"
                     : gray.empty() ? "unsupported image type"
                                    : ImageSizeMismatch(camera_, image.cols, image.rows);
    result.total_time_s = SecondsSince(start);
    result.total_cpu_s = ThreadCpuSeconds() - cpu_start;
    return result;
  }
  UWS_CHECK(mask.empty() || (mask.type() == CV_8UC1 && mask.size() == gray.size()),
            "vo: mask must be empty or CV_8U of the image size");
  timestamp_s_ = timestamp_s;
  result.tracking = tracker_.Track(gray, mask);
  MoveTracksToTruth();
  result.tracks = result.tracking.tracked;
  result.tracking_time_s = SecondsSince(start);
  result.tracking_cpu_s = ThreadCpuSeconds() - cpu_start;

  if (state_ == State::kTracking) {
    Track(mask, ranges, line_ranges, &result);
  } else {
    Initialize(mask, &result);
  }
  // Keep enough features alive between keyframes.
  if (int(tracker_.tracks().size()) < tracker_.target_count() / 2) {
    tracker_.Detect(mask, &result.tracking);
  }
  MoveTracksToTruth();  // those detected in this frame are seen by the truth here first
  if (result.world_from_camera) last_camera_from_world_ = result.world_from_camera->Inverse();
  result.total_time_s = SecondsSince(start);
  result.total_cpu_s = ThreadCpuSeconds() - cpu_start;
  return result;
}

void Odometry::SetReference(int frame_index) {
  reference_ = Reference{frame_index, {}};
  for (const auto& t : tracker_.tracks()) reference_->pixels[t.id] = t.pixel;
}

void Odometry::MoveTracksToTruth() {
  if (!options_.true_track_pixel) return;
  tracker_.MoveTracks(
      [&](const FeatureTrack& track) { return options_.true_track_pixel(track, timestamp_s_); });
}

void Odometry::MarkLost(const std::string& why, FrameResult* result) {
  result->status = FrameStatus::kLost;
  result->message = why;
  result->world_from_camera.reset();
  if (state_ == State::kTracking) {
    DiscardBundleAdjustment();
    if (!map_.keyframes.empty()) last_median_depth_ = MedianDepth(map_.keyframes.back());
    map_.Clear();
  }
  state_ = State::kLost;
  reference_.reset();
}

double Odometry::MedianDepth(const Keyframe& keyframe) const {
  std::vector<double> depths;
  for (const auto& [id, pixel] : keyframe.observations) {
    const MapPoint* point = map_.FindPoint(id);
    if (point) depths.push_back((keyframe.camera_from_world * point->position_world).z());
  }
  return depths.empty() ? last_median_depth_ : Median(depths);
}

std::optional<SparseMap> Odometry::BuildTwoViewMap(const RelativePoseResult& relative,
                                                   const std::vector<Ray>& rays1,
                                                   const std::vector<Ray>& rays2,
                                                   const std::vector<uint64_t>& ids, bool first_map,
                                                   double* rms_px) const {
  // Two keyframes: the reference at the origin, the current one from the
  // relative pose (unit baseline); triangulate the inliers.
  SparseMap map;
  Keyframe kf0, kf1;
  kf0.id = next_keyframe_id_;
  kf0.frame_index = reference_->frame_index;
  kf1.id = next_keyframe_id_ + 1;
  kf1.frame_index = frame_count_ - 1;
  kf1.timestamp_s = timestamp_s_;
  kf1.camera_from_world = relative.camera2_from_camera1;
  const Rigid3d world_from_kf1 = kf1.camera_from_world.Inverse();
  const double min_angle = options_.min_triangulation_angle_deg * M_PI / 180.0;
  std::unordered_map<uint64_t, Eigen::Vector2d> current;
  for (const auto& t : tracker_.tracks()) current[t.id] = t.pixel;
  std::vector<double> angles, depths;
  for (size_t i = 0; i < ids.size(); ++i) {
    if (!relative.inliers[i]) continue;
    const std::vector<Ray> rays = {rays1[i], rays2[i].Transformed(world_from_kf1)};
    const auto point = TriangulateRays(rays);
    const double angle = MaxRayAngle(rays);
    if (!point || angle < 0.5 * min_angle) continue;
    if ((kf1.camera_from_world * *point).z() <= 0) continue;
    map.points[ids[i]] = {ids[i], *point, 2};
    kf0.observations[ids[i]] = reference_->pixels.at(ids[i]);
    kf1.observations[ids[i]] = current.at(ids[i]);
    angles.push_back(angle);
    depths.push_back(point->z());
  }
  if (int(map.points.size()) < options_.min_init_matches || Median(angles) < min_angle) {
    return std::nullopt;
  }
  // Scale the two-view map so that its median depth is the expected one
  // (the prior at the first start, the previous map's after a loss): a
  // refractive camera is only described exactly at metric scale, since the
  // ray origins on the port are in metres.
  const double scale =
      (first_map ? options_.initial_median_depth_m : last_median_depth_) / Median(depths);
  kf1.camera_from_world.translation *= scale;
  for (auto& [id, point] : map.points) point.position_world *= scale;
  map.keyframes = {kf0, kf1};
  // Refine with the camera model (refractive for a flat port); the baseline
  // length is held (ceres::SphereManifold), the monocular gauge.
  BundleAdjustmentOptions ba = options_.ba;
  ba.max_iterations = std::max(ba.max_iterations, 20);
  ba.max_solver_time_s = std::max(ba.max_solver_time_s, 0.5);
  const BundleAdjustmentSummary summary = AdjustWindow(camera_, ba, &map, /*two_view_init=*/true);
  for (auto it = map.points.begin(); it != map.points.end();) {
    const bool seen = map.keyframes[0].observations.count(it->first) &&
                      map.keyframes[1].observations.count(it->first);
    it = seen ? std::next(it) : map.points.erase(it);
  }
  if (int(map.points.size()) < options_.min_init_matches) return std::nullopt;
  *rms_px = summary.final_rms_px;
  return map;
}

void Odometry::Initialize(const cv::Mat& mask, FrameResult* result) {
  result->status = state_ == State::kLost ? FrameStatus::kLost : FrameStatus::kInitializing;
  if (result->message.empty()) {
    result->message = state_ == State::kLost ? "re-initialising" : "initialising";
  }
  const double width = camera_.width;
  if (!reference_ || result->frame_index - reference_->frame_index > options_.max_init_frames) {
    tracker_.Detect(mask, &result->tracking);
    SetReference(result->frame_index);
    return;
  }
  std::vector<Ray> rays1, rays2;
  std::vector<uint64_t> ids;
  std::vector<double> flow;
  for (const auto& t : tracker_.tracks()) {
    const auto it = reference_->pixels.find(t.id);
    if (it == reference_->pixels.end()) continue;
    const auto r1 = camera_.BackProject(it->second), r2 = camera_.BackProject(t.pixel);
    if (!r1 || !r2) continue;
    rays1.push_back(*r1);
    rays2.push_back(*r2);
    ids.push_back(t.id);
    flow.push_back((t.pixel - it->second).norm());
  }
  if (int(ids.size()) < options_.min_init_matches) {
    // Too few features survive from the reference: start again from here.
    tracker_.Detect(mask, &result->tracking);
    SetReference(result->frame_index);
    return;
  }
  if (Median(flow) < options_.init_parallax_fraction * width) return;

  RelativePoseOptions relative_options;
  relative_options.threshold_rad = options_.ransac_threshold_px / camera_.intrinsics[0];
  std::vector<RelativePoseResult> candidates;
  const RelativePoseResult essential = EstimateRelativePose(rays1, rays2, relative_options);
  if (essential.success) candidates.push_back(essential);
  for (const auto& c : RelativePosesFromHomography(rays1, rays2, relative_options)) {
    candidates.push_back(c);
  }
  // Refine every candidate with the camera model and keep the one that
  // explains the tracks best.
  const bool first_map = num_maps_ == 0;
  std::optional<SparseMap> best;
  double best_rms = std::numeric_limits<double>::infinity();
  for (const RelativePoseResult& candidate : candidates) {
    if (candidate.num_inliers < options_.min_init_matches) continue;
    double rms = 0.0;
    std::optional<SparseMap> map = BuildTwoViewMap(candidate, rays1, rays2, ids, first_map, &rms);
    if (map && rms < best_rms) best_rms = rms, best = std::move(map);
  }
  if (!best) {
    result->message = candidates.empty() ? "initialisation: relative pose failed"
                                         : "initialisation: too little parallax or structure";
    return;
  }
  SparseMap map = std::move(*best);
  // Place the new map: the reference camera at the origin at the first
  // start, else where the last pose was (the motion through the gap is
  // unknown).
  map_ = std::move(map);
  const Rigid3d world_from_kf0 = first_map ? Rigid3d() : last_camera_from_world_.Inverse();
  const Rigid3d kf0_from_world = world_from_kf0.Inverse();
  for (Keyframe& kf : map_.keyframes) kf.camera_from_world = kf.camera_from_world * kf0_from_world;
  for (auto& [id, point] : map_.points)
    point.position_world = world_from_kf0 * point.position_world;
  next_keyframe_id_ += 2;
  ++num_maps_;
  state_ = State::kTracking;
  result->status = first_map ? FrameStatus::kTracked : FrameStatus::kReinitialized;
  result->message = first_map ? "initialised" : "re-initialised (new map, scale from previous)";
  result->keyframe = true;
  result->world_from_camera = map_.keyframes[1].WorldFromCamera();
  result->earlier_poses.emplace_back(map_.keyframes[0].frame_index,
                                     map_.keyframes[0].WorldFromCamera());
  result->map_matches = result->inliers = int(map_.points.size());
  last_keyframe_inliers_ = result->inliers;
  last_median_depth_ = MedianDepth(map_.keyframes[1]);
  // Drop the reference's tracks that did not make it into the map (outliers)
  // and refill the grid so the next keyframe can triangulate new points.
  std::vector<uint64_t> outliers;
  for (const auto& t : tracker_.tracks()) {
    if (!map_.points.count(t.id) && reference_->pixels.count(t.id)) outliers.push_back(t.id);
  }
  reference_.reset();
  tracker_.RemoveTracks(outliers);
  tracker_.Detect(mask, &result->tracking);
  tracker_.SetAnchor(mask, /*view_moved=*/true);  // two views with parallax
  for (const auto& t : tracker_.tracks()) map_.keyframes[1].observations[t.id] = t.pixel;
}

void Odometry::Track(const cv::Mat& mask, const std::vector<RangeConstraint>& passed_ranges,
                     const LineRanges& line_ranges, FrameResult* result) {
  if (pending_ba_.valid() && ++frames_since_ba_launch_ >= options_.async_merge_frames) {
    MergeBundleAdjustment(result);
  }
  std::vector<Ray> rays;
  std::vector<Eigen::Vector3d> points;
  std::vector<uint64_t> ids;
  std::vector<Eigen::Vector2d> pixels;
  for (const auto& t : tracker_.tracks()) {
    const MapPoint* point = map_.FindPoint(t.id);
    if (!point) continue;
    const auto ray = camera_.BackProject(t.pixel);
    if (!ray) continue;
    rays.push_back(*ray);
    points.push_back(point->position_world);
    ids.push_back(t.id);
    pixels.push_back(t.pixel);
  }
  result->map_matches = int(ids.size());
  if (int(ids.size()) < options_.min_pnp_inliers) {
    MarkLost("too few map points tracked (" + std::to_string(ids.size()) + ")", result);
    return;
  }
  AbsolutePoseOptions pnp_options;
  pnp_options.solver = options_.pose_solver;
  pnp_options.threshold_rad = options_.ransac_threshold_px / camera_.intrinsics[0];
  pnp_options.max_iterations = options_.pnp_max_iterations;
  const AbsolutePoseResult pnp = EstimateAbsolutePose(rays, points, pnp_options);
  if (!pnp.success || pnp.num_inliers < options_.min_pnp_inliers) {
    MarkLost("pose estimation failed (" + std::to_string(pnp.num_inliers) + " inliers)", result);
    return;
  }
  // Refine on the inliers by minimising the re-projection error (at most
  // max_refine_points of them, spread over the list: bounded work per frame).
  const CameraParams params(camera_);
  const Eigen::Quaterniond q0 = pnp.camera_from_world.rotation;
  double q[4] = {q0.x(), q0.y(), q0.z(), q0.w()};
  Eigen::Vector3d t = pnp.camera_from_world.translation;
  {
    std::vector<size_t> inlier_indices;
    for (size_t i = 0; i < ids.size(); ++i) {
      if (pnp.inliers[i]) inlier_indices.push_back(i);
    }
    const size_t stride =
        std::max<size_t>(1, inlier_indices.size() / size_t(options_.max_refine_points));
    ceres::Problem problem;
    ceres::HuberLoss* loss = new ceres::HuberLoss(options_.ba.huber_px);
    for (size_t k = 0; k < inlier_indices.size(); k += stride) {
      const size_t i = inlier_indices[k];
      const ReprojectionCost cost(params, options_.ba.method, options_.ba.taylor_iterations,
                                  pixels[i], 1.0);
      problem.AddResidualBlock(PoseReprojectionCost::Create(cost, points[i]), loss, q, t.data());
    }
    problem.SetManifold(q, new ceres::EigenQuaternionManifold);
    ceres::Solver::Options solver_options;
    solver_options.linear_solver_type = ceres::DENSE_QR;
    solver_options.max_num_iterations = 6;
    solver_options.function_tolerance = 1e-8;
    solver_options.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    ceres::Solve(solver_options, &problem, &summary);
  }
  const Rigid3d camera_from_world(Eigen::Quaterniond(q[3], q[0], q[1], q[2]), t);
  std::vector<uint64_t> outliers;
  int inliers = 0;
  for (size_t i = 0; i < ids.size(); ++i) {
    const auto pixel = camera_.Project(camera_from_world * points[i], options_.ba.method,
                                       options_.ba.taylor_iterations);
    if (pixel && (*pixel - pixels[i]).norm() <= options_.max_reprojection_px) {
      ++inliers;
    } else {
      outliers.push_back(ids[i]);
    }
  }
  result->inliers = inliers;
  if (inliers < options_.min_pnp_inliers) {
    MarkLost("too few inliers after refinement (" + std::to_string(inliers) + ")", result);
    return;
  }
  // A pose that jumps far from the last one is not believed.
  const double step =
      (camera_from_world.Inverse().translation - last_camera_from_world_.Inverse().translation)
          .norm();
  if (step > options_.max_step_depth_ratio * last_median_depth_) {
    MarkLost("implausible jump of " + std::to_string(step / last_median_depth_) + " median depths",
             result);
    return;
  }
  tracker_.RemoveTracks(outliers);
  result->status = FrameStatus::kTracked;
  result->world_from_camera = camera_from_world.Inverse();

  // Keyframe by parallax to the last keyframe, or when the map thins out.
  const Keyframe& last = map_.keyframes.back();
  std::vector<double> flow;
  for (const auto& tr : tracker_.tracks()) {
    const auto it = last.observations.find(tr.id);
    if (it != last.observations.end()) flow.push_back((tr.pixel - it->second).norm());
  }
  const bool view_moved = Median(flow) > options_.keyframe_parallax_fraction * camera_.width;
  const bool keyframe =
      (options_.max_frames_between_keyframes > 0 &&
       result->frame_index - last.frame_index >= options_.max_frames_between_keyframes) ||
      view_moved || inliers < options_.keyframe_min_tracked_ratio * last_keyframe_inliers_ ||
      (options_.keyframe_on_range_constraints && !passed_ranges.empty());
  if (!keyframe) return;
  std::vector<RangeConstraint> ranges = passed_ranges;
  if (line_ranges) {
    const std::vector<RangeConstraint> found = line_ranges(camera_from_world);
    ranges.insert(ranges.end(), found.begin(), found.end());
    result->line_ranges = int(found.size());
  }
  AddKeyframe(camera_from_world, mask, ranges, view_moved, result);
}

void Odometry::AddKeyframe(const Rigid3d& camera_from_world, const cv::Mat& mask,
                           const std::vector<RangeConstraint>& ranges, bool view_moved,
                           FrameResult* result) {
  // The BA in flight joins the map before this keyframe's points and
  // surface measurements change it.
  MergeBundleAdjustment(result);
  // New features first, so that they are observed in this keyframe.
  tracker_.Detect(mask, &result->tracking);
  Keyframe kf;
  kf.id = next_keyframe_id_++;
  kf.frame_index = result->frame_index;
  kf.timestamp_s = timestamp_s_;
  kf.camera_from_world = camera_from_world;
  for (const auto& t : tracker_.tracks()) kf.observations[t.id] = t.pixel;
  kf.range_constraints = ranges;
  map_.keyframes.push_back(std::move(kf));
  tracker_.SetAnchor(mask, view_moved);

  // Triangulate tracks seen in earlier keyframes of the window but not yet
  // in the map, from all their keyframe rays (widest baseline included).
  const int window = options_.ba.window_size;
  const int first = std::max(0, int(map_.keyframes.size()) - window);
  const Keyframe& newest = map_.keyframes.back();
  const double min_angle = options_.min_triangulation_angle_deg * M_PI / 180.0;
  for (const auto& [id, pixel] : newest.observations) {
    if (map_.points.count(id)) continue;
    std::vector<Ray> rays;
    std::vector<const Keyframe*> seen_by;
    for (int k = first; k < int(map_.keyframes.size()); ++k) {
      const Keyframe& kf_k = map_.keyframes[size_t(k)];
      const auto obs = kf_k.observations.find(id);
      if (obs == kf_k.observations.end()) continue;
      const auto ray = camera_.BackProject(obs->second);
      if (!ray) continue;
      rays.push_back(ray->Transformed(kf_k.WorldFromCamera()));
      seen_by.push_back(&kf_k);
    }
    if (rays.size() < 2 || MaxRayAngle(rays) < min_angle) continue;
    const auto point = TriangulateRays(rays);
    if (!point) continue;
    bool good = true;
    for (const Keyframe* kf_k : seen_by) {
      const auto projected = camera_.Project(kf_k->camera_from_world * *point);
      good = good && projected &&
             (*projected - kf_k->observations.at(id)).norm() <= options_.max_reprojection_px;
    }
    if (good) map_.points[id] = {id, *point, int(rays.size())};
  }
  if (options_.surface) AddSurfacePoints(&map_.keyframes.back());

  if (options_.async_bundle_adjustment) {
    LaunchBundleAdjustment();  // one BA in flight: the last one was merged above
  } else {
    result->bundle_adjustment = AdjustWindow(camera_, options_.ba, &map_);
    ApplyRemovedObservations(result->bundle_adjustment.removed_observations);
  }
  while (int(map_.keyframes.size()) > options_.ba.KeyframesRead()) map_.keyframes.pop_front();
  PruneMap();
  const Keyframe& adjusted = map_.keyframes.back();
  result->keyframe = true;
  result->world_from_camera = adjusted.WorldFromCamera();
  last_median_depth_ = MedianDepth(adjusted);
  int tracked_points = 0;
  for (const auto& t : tracker_.tracks()) tracked_points += map_.points.count(t.id) ? 1 : 0;
  last_keyframe_inliers_ = tracked_points;
}

void Odometry::ApplyRemovedObservations(const std::vector<uint64_t>& ids) {
  tracker_.RemoveTracks(ids);
  for (uint64_t id : ids) map_.points.erase(id);
}

void Odometry::PruneMap() {
  std::unordered_set<uint64_t> alive;
  for (const auto& t : tracker_.tracks()) alive.insert(t.id);
  for (const Keyframe& kf : map_.keyframes) {
    for (const auto& [id, pixel] : kf.observations) alive.insert(id);
  }
  for (auto it = map_.points.begin(); it != map_.points.end();) {
    it = alive.count(it->first) ? std::next(it) : map_.points.erase(it);
  }
  for (auto it = extrapolated_points_.begin(); it != extrapolated_points_.end();)
    it = map_.points.count(*it) ? std::next(it) : extrapolated_points_.erase(it);
  for (auto it = provisional_points_.begin(); it != provisional_points_.end();)
    it = map_.points.count(*it) ? std::next(it) : provisional_points_.erase(it);
}

}  // namespace uwscan::vo
