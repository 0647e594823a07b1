// The self-referenced scanner's pose estimation (thesis §5.4-5.5): visual
// odometry on the passive features of the same images that carry the laser,
// with the laser line masked out, the features coloured by the LED (the red
// channel of a raw Bayer frame when the laser is green, §5.5), and metric
// depth from the laser: the swept surface gives features their range, and
// each keyframe's profile the range of the map points the line meets there
// (line_ranges.h); both enter the windowed bundle adjustment as range
// constraints. The map is
// started from the laser surface too, so a hovering platform (millimetre
// motion, no baseline for two-view initialisation) is tracked from the
// first frames.
#pragma once

#include <atomic>
#include <deque>
#include <functional>
#include <memory>
#include <optional>

#include "uwscan/fusion/line_ranges.h"
#include "uwscan/fusion/pose_provider.h"
#include "uwscan/fusion/pose_smoother.h"
#include "uwscan/fusion/surface_model.h"
#include "uwscan/sensor/rig.h"
#include "uwscan/vo/odometry.h"

namespace uwscan::fusion {

// Diagnostics on simulated data (`uwscan reconstruct --oracle-depths`,
// `--oracle-tracks`): the true scene and trajectory, so that features can
// take their depth from the truth instead of the laser surface, or be
// tracked without error: what the odometry does with a perfect depth model
// or perfect tracks.
struct SimulatorTruth {
  // The true world_from_camera of the tracked camera at a timestamp.
  std::function<std::optional<Rigid3d>(double timestamp_s)> true_pose;
  // The nearest point where a ray of the true world meets the scene.
  std::function<std::optional<Eigen::Vector3d>(const Eigen::Vector3d& origin,
                                               const Eigen::Vector3d& direction)>
      intersect;
};

// The odometry's options for a self-referenced scan: vo::OdometryOptions
// with the re-projection residuals' robust loss (Huber) at 0.3 px of the
// tracked image instead of 1.5. The tracks' errors here are a noise of
// about 0.25 px with a heavy tail (tracks drawn along by the line, the
// light's fall-off, a patch's change since its anchor), and at 1.5 px that
// tail weighed fully in each frame's pose and the windowed BA
// (docs/BENCHMARKS.md, "A robust loss at the tracks' noise").
vo::OdometryOptions SelfReferencedOdometryOptions();

struct SelfReferencedOptions {
  vo::OdometryOptions odometry = SelfReferencedOdometryOptions();
  SurfaceModelOptions surface;
  // Range constraints where map points meet the laser line in a keyframe
  // (line_ranges.h), besides those from the accumulated surface. (`uwscan
  // reconstruct` sets it from ReconstructJob::line_ranges: by default with a
  // fixed laser only.)
  bool use_line_ranges = true;
  LineRangeOptions line_ranges;
  // The odometry tracks the passive image halved until it is at most this
  // wide (0: full resolution), with the camera scaled along; the laser is
  // still detected and triangulated at full resolution. Features at 640 px
  // are as good for a hover at 2 m and cost a quarter of the time.
  int max_tracking_width = 640;
  int mask_dilation_px = 4;  // around the detected line (halo, blur), full-resolution px
  double illumination_sigma_fraction = 0.01;  // high-pass scale, of the image width
  // Contrast equalised over a Gaussian of this fraction of the tracked
  // width (NormalizeIllumination); 0 = off. `uwscan reconstruct` sets it
  // (ReconstructJob::contrast_scale): on with a fixed laser, whose scans
  // move the texture through the light's whole fall-off, off on the
  // hovering servo sweeps, where it only adds noise.
  double contrast_sigma_fraction = 0.0;
  // The passive image is tracked in logarithm, log(I + this x its mean)
  // (NormalizeIllumination; 0 = linear, as before): the light's gain
  // across a patch, which moves as the patch moves through the fall-off,
  // becomes an offset the high pass removes. Linear, the tank scans' turns
  // came out 1.1 % short (0.985-0.993 of the truth) and their positions
  // long by as much; the offset keeps the dark parts' noise at most 3x
  // that of the mean's (BENCHMARKS.md, "The tracked image in logarithm").
  double log_offset_fraction = 0.5;
  static constexpr double kMaxLogOffsetFraction = 100.0;  // nearly linear by then
  // A pose that moves faster than a vehicle can is not believed: the frame
  // gets no pose and the map restarts from the last believed one.
  double max_rotation_rate_deg_s = 720.0;
  double max_speed_m_s = 20.0;
  // Poses are smoothed over +-N frames (quadratic fit, pose_smoother.h) and
  // come out N frames late; 0 switches smoothing off. `uwscan
  // reconstruct` keeps it within 0.14 s at slower frame rates
  // (ReconstructJob::smoothing_half_window).
  int smoothing_half_window = 10;
  // Frames held back while the laser sweeps enough surface for the scene's
  // plane (SurfaceModelOptions::min_plane_width_m): ~1 s at 144 Hz, where
  // the tank target's slowest sweep covers 5 cm in ~125 frames.
  int max_init_frames = 150;
  // The plane the start settles on must face the first held frame: seen
  // within 60 deg of its normal (SurfaceModel::DominantPlaneViewCosine);
  // else the start is refused and waits for more frames. Profiles of a
  // slow sweep whose platform moves so as to keep the line where it is in
  // the image, placed with too little motion, spread along the rays that
  // see the line, and any plane through the line fits them: one through or
  // near the camera gives features depths far off, and tracking on it
  // settles with the motion a tenth of the truth. Tank seed 103 thinned to
  // 14.4 Hz from each of its first ten frames: seven starts settled on
  // such planes (view cosines 0.006-0.24; the floor's 0.97), five of them
  // came out at 1.9-9.8x; refused below 0.2, two still did (0.235);
  // below 0.5, none (0.996-1.012). The simulator's hulls and transects,
  // seen face on, start as before (BENCHMARKS.md, "A start on a plane
  // through the camera").
  double min_start_plane_view_cosine = 0.5;
  // Frames between initialisation attempts while the hold grows; once it
  // is full (max_init_frames) its size stays, and every frame whose held
  // profiles span the plane is an attempt. Spacing those moved tank seed
  // 103's start and its scale (BENCHMARKS.md, "Two more unseen full scans,
  // ten more hulls").
  int init_attempt_every = 3;
  // Times the held frames are tracked on the starting surface and their
  // profiles placed again with those poses before tracking goes on: at
  // least init_refinements (0: placed once, with the guessed motion), then
  // more until the held frames' poses settle (rms change from one to the
  // next below init_settled_m and init_settled_deg), at most
  // max_init_refinements. A start whose first surface was far off (tank
  // seed 103: a slow sweep still inside the plane's RANSAC band, whose
  // plane came out as the light sheet, 86 deg to the floor) takes several
  // to come back; started after two, its trajectory came out a quarter
  // short.
  int init_refinements = 2;
  int max_init_refinements = 8;
  double init_settled_m = 0.002;
  double init_settled_deg = 0.05;
  // ... and while they converge: each change below this fraction of the one
  // before (StartConverging, from the third change on). 1: while each
  // change is smaller than the one before, however slowly; a start whose
  // poses shrink slowly from a far-off first surface needs those
  // refinements (tank seed 2003: 26, 19, 6, 5, 4, 3, 2.5 mm; stopped after
  // 19 mm at 0.7, its scale came out 1.6 % off, 0.3 % after all eight),
  // while the hulls' few held frames stop at the first change that grows
  // (HC29: 31, 17, 25 mm).
  double init_converging_ratio = 1.0;
  // A start whose refinements stopped unsettled because a change grew
  // (they had begun to diverge) is refused this many times in a scan, to
  // try again with more frames held. Tank seed 2309, never run before:
  // 2.3, 3.0, then 12.8 mm, and started there its scale came out 16.6 %
  // off; refused once, the next attempt settled (0.85 %). After that such
  // a start is taken as it is, with the warning: a hull's few held frames
  // rarely settle, nor do turbid water's. `uwscan reconstruct` sets it to 0
  // for a fixed laser (ReconstructJob::unsettled_start_refusals).
  int max_unsettled_start_refusals = 1;
  // Once the scan runs, each windowed BA stops after this many iterations
  // (the start's keep odometry.ba.max_iterations, 10). At 0.3 px of loss a
  // BA needs some ten to converge where 1.5 px needed five; the next
  // window's solve carries on from its result, and on five tank scans the
  // trajectories with 3, 5 or 10 came within 0.05 % of scale of each other,
  // while 5 keep the BA's time at what 1.5 px took. The start's refinements
  // need them: with 5 there too, a turbid start came out 12 % off, not 3 %.
  int running_ba_iterations = 5;
  // Place the held frames' profiles with a plain odometry's poses before
  // the map starts (GuessHeldMotion); on a hover it finds no parallax and
  // changes nothing.
  bool guess_held_motion = true;
  // Once tracking runs, the odometry sees every Nth frame only; the frames
  // between get their pose interpolated (slerp) from the two tracked frames
  // around them, and their profiles join the surface with it. At 144 Hz a
  // hovering platform's motion is smooth over a few frames: with 2 the
  // tank hovers' clouds stay within the seeds' spread and the scan runs in
  // real time (BENCHMARKS.md). 1: every frame. `uwscan reconstruct` sets
  // it from the frame rate (ReconstructJob::track_every).
  int track_every = 1;
  // ... and, with track_every > 1, tracks the mean of the frames since the
  // tracked one before (the skipped ones and its own), taken at their mean
  // time; every frame then gets its pose between the two tracked times
  // around it. The image noise the tracks follow falls by sqrt(track_every),
  // as with a longer exposure: at 144 Hz (2) on eleven tank scans the pose's
  // error per frame fell by 21-41 % (BENCHMARKS.md, "Two frames tracked as
  // one"). The start's held frames are tracked one by one as before.
  bool average_skipped_frames = true;
  // Once a start attempt has been refused because its held profiles,
  // placed with tracked poses, were too narrow for the plane, each later
  // one first tracks every Nth held frame only (0: track_every): that
  // first tracking mostly screens whether they span it now, and a hover's
  // motion is smooth over a few tens of milliseconds. The refinements
  // after it track every track_every-th as before. A scan whose start is
  // refused again and again (a slow sweep that the platform follows: tank
  // seed 103, eight refusals) spent most of its start's time on those
  // screens. `uwscan reconstruct` screens at up to 40 Hz
  // (ReconstructJob::start_screen_every; BENCHMARKS.md, "The refused
  // starts screened at 36 Hz"). A first attempt is as before, and so is one
  // after a refusal for poses that would not settle.
  int start_screen_every = 0;
  // When set, features take their depth from the truth (SimulatorTruth), not
  // from the laser surface; the surface still decides when the map starts.
  std::shared_ptr<const SimulatorTruth> depth_oracle;
  // When set, each feature track is moved in every frame to where the
  // scene point seen at its first pixel (with the true pose of that frame)
  // truly projects; no tracking error is left.
  std::shared_ptr<const SimulatorTruth> track_oracle;
  // A later pass over the same frames (`uwscan reconstruct --passes 2|3`):
  // the surface the pass before measured over the whole scan, and the frame
  // the first pass's map started at, which is this pass's origin too. The
  // map starts there at once on that surface, so features get the depth of
  // surfaces the laser reaches only later in the scan (a shaft in front of
  // a hull) from the first frame on.
  std::shared_ptr<const SurfaceModel> prior_surface;
  int prior_first_frame = -1;
  void Check() const;
};

class SelfReferencedPoseProvider : public PoseProvider {
 public:
  SelfReferencedPoseProvider(const Camera& camera, int laser_channel,
                             const SelfReferencedOptions& options = {});
  std::vector<PoseUpdate> Add(const FrameInput& frame) override;
  std::vector<PoseUpdate> Finish() override;
  std::string Name() const override { return "self-referenced visual odometry"; }
  nlohmann::json Details() const override;
  // After Finish: the surface measured over the scan (nullptr if the map
  // never started), and the frame the map started at.
  std::shared_ptr<const SurfaceModel> MeasuredSurface() const { return surface_; }
  int FirstFrameWithPose() const { return init_frame_; }
  std::vector<PoseUpdate> Preliminary() const override { return preliminary_; }
  // The tracked image and dilated line mask (thread-safe: reads what the
  // constructor set and last_tracked_index_). With track_every > 1 only for
  // the frames Add is expected to track (those it holds at the start: all;
  // once running: every track_every-th frame given to PrepareAhead after
  // the last tracked one, so that frames a live run dropped before both
  // count for neither), the others get an empty PreparedFrame: preparing
  // all would make the reading thread the slower one. A frame guessed wrong
  // is prepared in Add (Details: tracked_images_made_late).
  bool PreparesAhead() const override { return true; }
  PreparedFrame PrepareAhead(const FrameInput& frame) const override;
  // The camera of the image PrepareAhead makes from this stored frame.
  Camera TrackedCamera(const cv::Mat& frame) const;

  // The image the odometry tracks: the LED's colour channel of a raw Bayer
  // or colour frame (not the laser's), else the frame itself.
  static cv::Mat PassiveImage(const cv::Mat& image, const std::string& bayer, int laser_channel);
  // The colour (laser::kRed or kBlue) the passive image takes: red unless
  // the laser is red.
  static int PassiveColour(int laser_channel) {
    return laser_channel == laser::kRed ? laser::kBlue : laser::kRed;
  }
  // 8-bit high pass of the passive image (local mean removed, Gaussian of
  // `sigma_px`) with its contrast equalised over `contrast_sigma_px` (0:
  // not), so that lights moving with the camera do not bias tracking;
  // with `log_offset` > 0 of log(image + log_offset x its mean), in grey
  // levels of the mean (SelfReferencedOptions::log_offset_fraction).
  static cv::Mat NormalizeIllumination(const cv::Mat& image, double sigma_px,
                                       double contrast_sigma_px = 0.0, double log_offset = 0.0);
  // Where a colour (laser::kRed or kBlue) sits in each 2x2 cell of a raw
  // mosaic named like rig.yaml's `bayer` (rggb ...): column, row; none for
  // green (two samples per cell) or "none".
  static std::optional<cv::Point> BayerSampleOffset(const std::string& bayer, int rgb_channel);
  // That colour's own samples of the raw mosaic: a half-resolution image.
  static cv::Mat BayerChannel(const cv::Mat& raw, const cv::Point& offset);
  // The mean of several raw mosaics' samples of that colour, unrounded:
  // CV_32F in 8-bit grey levels (16-bit samples / 256), the unit
  // NormalizeIllumination works in.
  static cv::Mat BayerChannelMean(const std::vector<cv::Mat>& raws, const cv::Point& offset);
  // The camera of BayerChannel's image: half-resolution pixel x is
  // full-resolution pixel 2 x + offset.
  static Camera BayerChannelCamera(const Camera& camera, const cv::Point& offset);

  // What the odometry tracks, shared with `uwscan vo`: halvings that bring
  // `width` to at most `max_width` (0: none), not below 320 px;
  static int TrackingHalvings(int width, int max_width);
  // the camera halved so often, the first halving through a Bayer colour's
  // own samples when `bayer_offset` is set (BayerChannelCamera);
  static Camera TrackingCamera(const Camera& camera, int halvings,
                               const std::optional<cv::Point>& bayer_offset);
  // the passive image at that camera's size (BayerChannel or PassiveImage,
  // then 2x2 averages), not yet high-passed;
  static cv::Mat TrackedPassiveImage(const cv::Mat& raw, const std::string& bayer,
                                     int laser_channel,
                                     const std::optional<cv::Point>& bayer_offset,
                                     const cv::Size& tracked);
  // the same for the mean of several frames (SelfReferencedOptions::
  // average_skipped_frames), unrounded, as BayerChannelMean;
  static cv::Mat TrackedPassiveImage(const std::vector<cv::Mat>& raws, const std::string& bayer,
                                     int laser_channel,
                                     const std::optional<cv::Point>& bayer_offset,
                                     const cv::Size& tracked);
  // and a full-resolution mask at that size: a tracked pixel is masked if
  // any of its full-resolution pixels is.
  static cv::Mat TrackedMask(const cv::Mat& mask, const cv::Size& tracked);

  // Whether the held frames' poses still converge at the start, given the
  // rms change of each refinement after the first, in order: while there
  // are fewer than three, or the last is below `ratio`
  // (init_converging_ratio) times the one before. The second change is not
  // held to the first: the surface the held frames were first placed on,
  // with the platform moving several centimetres while they were taken, can
  // take two refinements to turn into place, the second moving them more
  // (tank seeds 2063 and 2069: 34 then 43 mm and 20 then 38 mm, then 2.8
  // and 5.3 mm, settled after one more; stopped at the second, the scan
  // warned and ran again on half the image, at half the speed).
  static bool StartConverging(const std::vector<double>& moved_m, double ratio);

 private:
  struct Held {
    FrameInput input;  // image owned (cloned)
    cv::Mat mask;
    laser::Profile profile;
    // The time the tracked image stands for when it is the mean of the
    // skipped frames and this one (average_skipped_frames).
    std::optional<double> averaged_time_s;
    // Where tracking put it in an initialisation attempt (relative to the
    // first held frame), for placing its profile in the next attempt.
    std::optional<Rigid3d> pose_guess;
    // Its pose from the plain odometry of the held frames (guess_odometry_),
    // in that odometry's own world.
    int guess_index = -1;
    std::optional<Rigid3d> guess_world_from_camera;
  };
  // While frames are held: a plain (two-view started) odometry on them, its
  // scale prior the laser's median range. A fixed laser on a moving
  // platform draws the same line in every held frame, so placed with the
  // first pose their profiles never spread across the line and the surface
  // never gets its plane; placed where this odometry puts them, they do.
  void GuessHeldMotion(Held* held);
  // The passive colour straight from the raw mosaic if the frames are raw
  // and tracking is at half resolution or less (chosen on the first frame).
  std::optional<cv::Point> ChooseBayerOffset(const cv::Mat& frame) const;
  // The tracked image (high-passed) of the mean of `raws` (one: that
  // frame's) and, if every line mask is given, their union dilated, at its
  // size; `tracking` is the camera of `bayer_offset`'s image
  // (TrackingCamera).
  PreparedFrame MakePrepared(const std::vector<cv::Mat>& raws,
                             const std::vector<const cv::Mat*>& line_masks,
                             const std::optional<cv::Point>& bayer_offset,
                             const Camera& tracking) const;
  // The line mask dilated by mask_dilation_px, at the tracked size.
  cv::Mat TrackedLineMask(const cv::Mat& line_mask, const cv::Size& tracked) const;
  std::vector<PoseUpdate> TryInitialize();
  // Whether the plane the start settled on faces the first held frame
  // (min_start_plane_view_cosine; any plane without extrapolate_plane).
  bool StartPlaneFacesCamera(const SurfaceModel& surface) const;
  // A start attempt refused (counted): its odometry and surfaces dropped,
  // the held frames kept with the poses it tracked, for the next attempt.
  void RefuseStart();
  // A new odometry on surface_, started at the first held frame; false (and
  // no odometry) if it cannot start there.
  bool StartOdometry(const Rigid3d& origin);
  // Add without the bookkeeping for PrepareAhead.
  std::vector<PoseUpdate> AddFrame(const FrameInput& frame);
  // OdometryOptions::true_track_pixel from options_.track_oracle.
  std::function<std::optional<Eigen::Vector2d>(const vo::FeatureTrack&, double)> TrueTrackPixels()
      const;
  // Held frame i's pose_guess, else that of the nearest earlier frame with
  // one, else `origin` (the first held frame's pose).
  Rigid3d PoseGuess(size_t i, const Rigid3d& origin) const;
  std::optional<PoseUpdate> Track(const Held& frame);
  // Counts the frame's windowed BA, if it ran one (`at_start`: in a start
  // attempt, whose adjustments can move the start and so the trajectory).
  void CountBundleAdjustment(const vo::FrameResult& result, bool at_start);
  // The tracked image and mask of a frame (the input's image is replaced);
  // `with_skipped`: of the mean of skipped_'s frames and this one, at their
  // mean time (average_skipped_frames), the mask the union of theirs.
  Held Prepare(const FrameInput& frame, const cv::Mat& line_mask, bool with_skipped) const;
  // Whether the frame Add tracks next is the mean of the frames since the
  // last tracked one.
  bool Averaging() const { return options_.average_skipped_frames && options_.track_every > 1; }
  // Tracks `frame`, then places the skipped frames before it between the
  // last pose and its own (options_.track_every).
  std::vector<PoseUpdate> TrackAfterSkipped(const Held& frame);
  // At the end of the sequence: pending_'s frames at the last pose.
  std::vector<PoseUpdate> PlacePending();
  // How far after the last tracked time a pending frame may be placed.
  static constexpr double kMaxPendingS = 0.1;
  // Tracking lost or not believed: drop the map and hold frames again.
  void Restart();
  // Raw poses through the smoother; a gap flushes it.
  void Emit(const std::optional<PoseUpdate>& raw, double timestamp_s, std::vector<PoseUpdate>* out);
  std::unique_ptr<PoseSmoother> smoother_;
  std::vector<PoseUpdate> preliminary_;  // raw poses of the last Add

  Camera camera_;
  Camera tracking_camera_;  // camera_ scaled to the tracked image
  int tracking_halvings_ = 0;
  std::optional<cv::Point> bayer_offset_;  // raw frames: the passive colour's samples
  int laser_channel_;
  SelfReferencedOptions options_;
  std::unique_ptr<vo::Odometry> odometry_;
  std::shared_ptr<SurfaceModel> surface_;
  // While no pose: the surface of the first init_surface_frames_ held frames.
  std::shared_ptr<SurfaceModel> init_surface_;
  size_t init_surface_frames_ = 0;
  std::deque<Held> held_;
  // Frames not tracked since the last tracked one (track_every > 1): the
  // raw image and the line mask kept (shared with the caller, which hands
  // in new ones with every frame), prepared only if the sequence ends
  // before the next tracked frame. (The held frames skipped when tracking
  // starts are prepared already; the last held frame is always tracked, so
  // none of them is left here.)
  struct Skipped {
    FrameInput input;  // detection and profile unset
    cv::Mat line_mask;
    laser::Profile profile;
  };
  // A frame not tracked itself, at `pose`: its profile joins the surface
  // and the pose goes out (counted in interpolated_).
  void PlaceBetween(const Skipped& frame, const Rigid3d& pose, std::vector<PoseUpdate>* updates);
  std::vector<Skipped> skipped_;
  // Frames of averaged tracked images later than the image's time (the
  // tracked frame itself, mostly): placed once the next tracked pose is
  // known (images dropped).
  std::vector<Skipped> pending_;
  // PrepareAhead's frames since the last it prepared to be tracked, for the
  // mean of the next (average_skipped_frames; that thread's only).
  struct AheadFrame {
    int index = 0;
    cv::Mat image;      // as stored (shared, not copied)
    cv::Mat line_mask;  // full resolution (shared)
    bool has_mask = false;
  };
  mutable std::vector<AheadFrame> ahead_frames_;
  // The indices of the last frames PrepareAhead was given (that thread's
  // only), to count those since the last tracked one.
  mutable std::deque<int> ahead_seen_;
  static constexpr size_t kAheadSeen = 64;
  std::unique_ptr<vo::Odometry> guess_odometry_;
  int guess_frames_ = 0;
  bool guess_failed_ = false;
  bool running_ = false;
  // The index of the frame Add tracked last once running (-1: every frame
  // is taken, held at the start), for PrepareAhead on another thread.
  std::atomic<int> last_tracked_index_{-1};
  std::optional<Rigid3d> last_pose_;
  double last_time_s_ = 0.0;
  int implausible_ = 0;
  // Statistics.
  int interpolated_ = 0;  // frames placed between tracked ones
  int averaged_ = 0;      // tracked images that were the mean of several frames
  // Tracked images made on the caller's thread: the reading thread had
  // guessed another frame to track (PrepareAhead), or made none.
  mutable int prepared_late_ = 0;
  int frames_ = 0, tracked_ = 0, lost_ = 0, reinitialisations_ = 0, dropped_ = 0, keyframes_ = 0;
  int init_frame_ = -1;
  // The start's refinements (init_refinements), whether its poses settled,
  // and their last rms change (none if no refinement tracked any of the
  // held frames the one before had).
  int init_refinements_done_ = 0;
  bool init_settled_ = false;
  std::optional<PoseChange> init_last_change_;
  // Start attempts whose held frames, placed with their tracked poses, no
  // longer spanned the scene's plane (their surface had one before), or
  // settled on a plane through the camera.
  int init_refused_ = 0;
  int init_refused_unsettled_ = 0;  // of those, refinements that diverged
  int init_refused_narrow_ = 0;     // of those, profiles too narrow for the plane once tracked
  long tracks_cut_by_line_ = 0, tracks_reacquired_ = 0;  // thesis §5.5 track association
  long line_ranges_ = 0;  // range constraints where map points met the laser line
  // All windowed BAs, and those of the start's attempts among them.
  int bundle_adjustments_ = 0, bundle_adjustments_time_limited_ = 0, init_bundle_adjustments_ = 0;
  int init_frames_tracked_ = 0;  // held frames tracked by the start's attempts, all of them
};

}  // namespace uwscan::fusion
