// Monocular visual odometry for flat-port (or pinhole) cameras, thesis §5.2:
// Harris + pyramidal KLT tracking with a per-frame mask, five-point
// initialisation refined with the refractive model, (generalised) P3P
// tracking against the map with re-projection refinement, keyframes by
// parallax, triangulation across the widest baseline and windowed bundle
// adjustment. Frames come one by one; memory is bounded by the window.
//
// Interfaces for the fusion (thesis §5.4): a mask of pixels to ignore per
// frame (the laser line), range constraints passed with a frame (added to
// the windowed BA when the frame is a keyframe), an ExtraResidualCallback in
// BundleAdjustmentOptions, and read access to the map (keyframes, points).
#pragma once

#include <functional>
#include <future>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "uwscan/sensor/camera.h"
#include "uwscan/vo/feature_tracker.h"
#include "uwscan/vo/geometric_solvers.h"
#include "uwscan/vo/map.h"
#include "uwscan/vo/windowed_bundle_adjuster.h"

namespace uwscan::vo {

// Where a ray meets a metrically measured surface, and how well that is known.
struct SurfaceHit {
  Eigen::Vector3d point_world;
  double sigma_m = 0.003;
  // Not measured around the ray but extrapolated (a dominant plane): such
  // points are measured again at later keyframes, once the laser has swept
  // there, and moved if the measurement disagrees.
  bool extrapolated = false;
  // Extrapolated from a surface measured too narrowly to be trusted far
  // from its points (a plane fitted on a narrow band of laser lines, whose
  // tilt the poses' errors set): such points are placed again, once, on
  // the surface as it is when it is no longer provisional.
  bool provisional = false;
};

enum class FrameStatus {
  kInitializing,   // no map yet (start of the sequence): no pose
  kTracked,        // pose from the map
  kLost,           // tracking lost, waiting for re-initialisation: no pose
  kReinitialized,  // first pose of a new map after a loss; the gap before it is marked
  kInvalid,        // frame rejected (empty, wrong size or type): no pose, state unchanged
};
const char* FrameStatusName(FrameStatus status);

struct OdometryOptions {
  FeatureTrackerOptions tracker;
  BundleAdjustmentOptions ba;
  AbsolutePoseSolver pose_solver = AbsolutePoseSolver::kGP3P;
  double ransac_threshold_px = 1.5;
  int pnp_max_iterations = 100;
  int min_init_matches = 40;
  // Median feature displacement needed to initialise / to start a keyframe,
  // as a fraction of the image width.
  double init_parallax_fraction = 0.05;
  double keyframe_parallax_fraction = 0.04;
  // A keyframe is also made when the tracked map points fall below this
  // fraction of those of the last keyframe.
  double keyframe_min_tracked_ratio = 0.6;
  // ... and at the latest after this many frames (0 = never): a hovering
  // platform makes no parallax, and without keyframes the windowed BA and
  // the laser depths of new points (fusion) never refresh the map — on the
  // 2000-frame hover the target's plane std went 3.2 -> 1.7 mm with 30
  // (0.2 s at 144 Hz).
  int max_frames_between_keyframes = 30;
  int max_init_frames = 40;  // the initialisation reference is renewed after this
  int min_pnp_inliers = 15;
  int max_refine_points = 150;  // pose refinement uses at most this many inliers
  double min_triangulation_angle_deg = 1.0;
  double max_reprojection_px = 2.5;
  // Largest plausible motion between two frames relative to the median scene
  // depth; a larger jump is treated as a tracking failure.
  double max_step_depth_ratio = 0.5;
  // A frame passed with range constraints becomes a keyframe, so the window
  // holds them (not one whose only ranges come from ProcessFrame's
  // `line_ranges`).
  bool keyframe_on_range_constraints = true;
  // Depth from an active sensor (fusion, thesis §5.4): where a world ray
  // (origin, unit direction) meets the metrically measured scene, if known.
  // When set, tracks that cannot be triangulated (too little baseline, as
  // on a hovering platform) get their map point there at keyframes, with a
  // range constraint of the hit's uncertainty in that keyframe.
  std::function<std::optional<SurfaceHit>(const Eigen::Vector3d&, const Eigen::Vector3d&)> surface;
  // A depth the surface only extrapolated can belong to what lies behind
  // the feature (a hull behind a shaft). Such a map point is made only once
  // an earlier keyframe saw the feature too and the point re-projects there
  // within this many pixels; not while the map is being started or holds
  // fewer than min_map_points_to_defer points. 0: made at once, unchecked.
  double max_extrapolated_disagreement_px = 1.0;
  // Diagnostics on simulated data (`uwscan reconstruct --oracle-tracks`):
  // where the scene point a track follows truly is in the image at a time.
  // When set, every track is moved there after tracking and detection
  // (none: it keeps its tracked pixel): what the odometry does with perfect
  // tracks.
  std::function<std::optional<Eigen::Vector2d>(const FeatureTrack&, double timestamp_s)>
      true_track_pixel;
  int min_map_points_to_defer = 50;
  // Scale prior: the expected median distance to the scene at the start
  // (altitude, laser range). Monocular VO is up to scale, but a refractive
  // camera is exact only at metric scale (its ray origins on the port are in
  // metres), so the map starts near it; range constraints then fix it.
  double initial_median_depth_m = 2.0;
  // Run the windowed BA of each keyframe on a second thread (on a copy of
  // the window) while the frames after it are tracked against the map as it
  // was. Its result joins the map at the async_merge_frames-th frame after
  // the keyframe, or at the next keyframe if that comes first, waiting for
  // the BA if it is not done: where the result lands does not depend on
  // thread timing, so runs are reproducible. extra_residuals is then called
  // on that thread.
  bool async_bundle_adjustment = false;
  int async_merge_frames = 8;
  void Check() const;
};

// Frames faster than this: the controllers (`uwscan reconstruct`, `uwscan
// vo`) run the windowed BA on its own thread unless told otherwise, since a
// keyframe's BA would hold up several frames there.
inline constexpr double kAsyncBundleAdjustmentAboveHz = 100.0;
inline bool AsyncBundleAdjustmentByDefault(double mean_frame_interval_s) {
  return mean_frame_interval_s > 0.0 &&
         1.0 / mean_frame_interval_s > kAsyncBundleAdjustmentAboveHz + 1e-9;
}

struct FrameResult {
  int frame_index = 0;  // running count of ProcessFrame calls
  double timestamp_s = 0.0;
  FrameStatus status = FrameStatus::kInitializing;
  std::optional<Rigid3d> world_from_camera;
  bool keyframe = false;
  int tracks = 0;       // features tracked into this frame
  int map_matches = 0;  // of them with a map point
  int inliers = 0;      // pose inliers
  int line_ranges = 0;  // keyframes: range constraints ProcessFrame's line_ranges found
  std::string message;  // why a frame was lost or rejected
  // Poses of earlier frames that become known with this one (the
  // initialisation reference frame): frame_index -> world_from_camera.
  std::vector<std::pair<int, Rigid3d>> earlier_poses;
  TrackingStats tracking;
  // When keyframe; with async_bundle_adjustment, that of the BA merged at
  // this frame.
  BundleAdjustmentSummary bundle_adjustment;
  double tracking_time_s = 0.0;  // features only (wall clock)
  double total_time_s = 0.0;
  // The same as CPU time of the calling thread: on a shared machine this
  // is the cost of the frame, the wall clock includes waiting for a core.
  double tracking_cpu_s = 0.0;
  double total_cpu_s = 0.0;
};

class Odometry {
 public:
  Odometry(const Camera& camera, const OdometryOptions& options = {});
  ~Odometry();
  Odometry(const Odometry&) = delete;
  Odometry& operator=(const Odometry&) = delete;

  // `image`: 8-bit grey, 16-bit grey or 8-bit colour (green channel is
  // used), of the camera's size. `mask`: empty or CV_8U of the image size,
  // non-zero = ignore (e.g. laser::LaserDetection::mask). `ranges` refer to
  // map point ids seen in this frame. Never throws on bad image content;
  // throws uwscan::Error for a mask of the wrong size/type (a caller bug).
  // `line_ranges`, when set, is called when the frame becomes a keyframe
  // (parallax, a thinning map, max_frames_between_keyframes), with its pose
  // (camera_from_world), and returns range constraints measured in this
  // frame for map points it finds there (thesis §5.4: map points re-projected
  // into the frame where they meet the laser line). They do not make a
  // keyframe themselves: on a hover, a keyframe at every frame the line met
  // the map tripled the trajectory error (tank seed 9: ATE 1.0 -> 3.1 mm).
  using LineRanges = std::function<std::vector<RangeConstraint>(const Rigid3d&)>;
  FrameResult ProcessFrame(const cv::Mat& image, const cv::Mat& mask, double timestamp_s,
                           const std::vector<RangeConstraint>& ranges = {},
                           const LineRanges& line_ranges = {});

  // Starts a map at this frame from `options.surface` instead of two-view
  // geometry: the frame becomes the first keyframe at `world_from_camera`
  // and every feature whose ray meets the surface a map point. Returns
  // status kTracked on success; kInitializing (state unchanged otherwise)
  // when too few features have a depth yet.
  FrameResult InitializeFromSurface(const cv::Mat& image, const cv::Mat& mask, double timestamp_s,
                                    const Rigid3d& world_from_camera);

  const SparseMap& map() const { return map_; }
  const std::vector<FeatureTrack>& tracks() const { return tracker_.tracks(); }
  const Camera& camera() const { return camera_; }
  const OdometryOptions& options() const { return options_; }
  // The windowed BAs launched from now on stop after this many iterations
  // (BundleAdjustmentOptions::max_iterations).
  void SetBundleAdjustmentIterations(int iterations);
  int num_maps() const { return num_maps_; }  // 1 + re-initialisations
  // Map points placed again once the surface they had been extrapolated
  // from was no longer provisional (SurfaceHit::provisional).
  int provisional_points_placed_again() const { return provisional_placed_again_; }

 private:
  struct Reference {
    int frame_index = 0;
    std::unordered_map<uint64_t, Eigen::Vector2d> pixels;
  };
  void Track(const cv::Mat& mask, const std::vector<RangeConstraint>& ranges,
             const LineRanges& line_ranges, FrameResult* result);
  void Initialize(const cv::Mat& mask, FrameResult* result);
  std::optional<SparseMap> BuildTwoViewMap(const RelativePoseResult& relative,
                                           const std::vector<Ray>& rays1,
                                           const std::vector<Ray>& rays2,
                                           const std::vector<uint64_t>& ids, bool first_map,
                                           double* rms_px) const;
  void SetReference(int frame_index);
  void MarkLost(const std::string& why, FrameResult* result);
  // Moves the tracks to options_.true_track_pixel's pixels, if set.
  void MoveTracksToTruth();
  // `view_moved`: made for parallax (FeatureTracker::SetAnchor).
  void AddKeyframe(const Rigid3d& camera_from_world, const cv::Mat& mask,
                   const std::vector<RangeConstraint>& ranges, bool view_moved,
                   FrameResult* result);
  void PruneMap();
  // See OdometryOptions::max_extrapolated_disagreement_px.
  bool ExtrapolatedDepthAgrees(const Keyframe& keyframe, uint64_t id,
                               const Eigen::Vector3d& point_world) const;
  // Map points for the newest keyframe's tracks from options_.surface.
  int AddSurfacePoints(Keyframe* keyframe);
  // Moves a map point and drops the range constraints that held it.
  void MovePoint(MapPoint* point, const Eigen::Vector3d& position_world);
  // Asynchronous BA (odometry_async.cc).
  struct AdjustedWindow {
    SparseMap window;
    BundleAdjustmentSummary summary;
  };
  void LaunchBundleAdjustment();
  // Waits for the BA in flight, if any, and merges its result; its summary
  // goes into `result` (the frame it is merged at), when given.
  void MergeBundleAdjustment(FrameResult* result = nullptr);
  void DiscardBundleAdjustment();
  void ApplyRemovedObservations(const std::vector<uint64_t>& ids);
  double MedianDepth(const Keyframe& keyframe) const;

  Camera camera_;
  OdometryOptions options_;
  FeatureTracker tracker_;
  SparseMap map_;
  std::unordered_set<uint64_t> extrapolated_points_;  // depth from an extrapolated surface
  std::unordered_set<uint64_t> provisional_points_;   // ... from a provisional one
  enum class State { kInitializing, kTracking, kLost } state_ = State::kInitializing;
  std::optional<Reference> reference_;
  int frame_count_ = 0;
  double timestamp_s_ = 0.0;
  uint64_t next_keyframe_id_ = 0;
  int num_maps_ = 0;
  int last_keyframe_inliers_ = 0;
  int remeasured_moved_ = 0;          // extrapolated points moved to the measured surface
  int provisional_placed_again_ = 0;  // provisional points placed on the settled surface
  Rigid3d last_camera_from_world_;    // last emitted pose
  double last_median_depth_ = 2.0;    // scale carried over a re-initialisation
  std::future<AdjustedWindow> pending_ba_;
  int frames_since_ba_launch_ = 0;
};

// 8-bit grey view of a frame (16-bit scaled by its used bit depth, colour ->
// green channel); empty if the type is unsupported.
cv::Mat ToGray8(const cv::Mat& image);

}  // namespace uwscan::vo
