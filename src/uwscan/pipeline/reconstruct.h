// Controller of `uwscan reconstruct`: streams a dataset through laser
// detection, triangulation and pose estimation and places every laser
// profile in the world (architecture.md, "Data flow").
#pragma once

#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "uwscan/fusion/pose_provider.h"
#include "uwscan/fusion/self_referenced.h"
#include "uwscan/io/dataset.h"
#include "uwscan/io/image.h"
#include "uwscan/laser/detector.h"
#include "uwscan/laser/profile.h"

namespace uwscan {

struct ReconstructJob {
  std::filesystem::path dataset;
  std::filesystem::path out;
  std::optional<std::filesystem::path> poses_file;  // external trajectory (TUM) instead of VO
  // A poses_file on another clock or of another body (an INS's): the pose
  // it stamps t is the camera's at t + poses_time_offset_s, and
  // world_from_camera = its pose * poses_body_from_camera.
  double poses_time_offset_s = 0.0;
  std::optional<Rigid3d> poses_body_from_camera;
  bool motion_compensation = true;  // false: cloud.ply too is placed with the first pose
  std::string camera_name;          // default: the first camera
  std::string laser_name;           // default: the first laser
  laser::DetectorOptions detector;  // scan direction and colour come from the rig
  fusion::SelfReferencedOptions self_referenced;
  // Range constraints where map points meet the laser line (thesis §5.4,
  // SelfReferencedOptions::use_line_ranges): unset = with a fixed laser
  // only. A fixed laser on a moving platform leaves the surface's reference
  // view behind and needs them to keep the scale (20 m transects: Sim(3)
  // scale 0.958-0.990 -> 0.994-0.998); a servo sweep measures the features'
  // depths itself, and there they hurt a hull with a shaft in front (shaft
  // residual worse on 3 seeds of 4, median 8.2 vs 3.9 mm) and do nothing
  // on the tank.
  std::optional<bool> line_ranges;
  // Starts whose refinements began to diverge, refused to wait for more
  // frames (SelfReferencedOptions::max_unsettled_start_refusals, which this
  // sets): unset = that option's 1 on a servo sweep, which gains surface
  // while the start waits, and 0 with a fixed laser on a moving platform,
  // where waiting only adds motion for the held frames' poses to explain
  // (a 40-frame transect refused once: point error 3.5 -> 22 mm).
  std::optional<int> unsettled_start_refusals;
  // The tracked image's contrast equalised over a Gaussian of this fraction
  // of its width (SelfReferencedOptions::contrast_sigma_fraction, which
  // this sets); unset = kFixedLaserContrastScale with a fixed laser, 0 on
  // servo sweeps. A fixed laser scans by the platform's motion, which
  // carries the texture through the light's whole fall-off: on 13 20 m
  // transects ATE 41-77 -> 7-31 mm and Sim(3) scale 0.990-0.995 ->
  // 0.995-0.999 (BENCHMARKS.md, "Contrast equalised in the self-referenced
  // scan"); a hover barely moves it, and there the equalisation only adds
  // noise (hull shafts worse on the coastal seeds that need it most).
  std::optional<double> contrast_scale;
  static constexpr double kFixedLaserContrastScale = 0.05;  // as `uwscan vo`
  // Ignore line candidates that behave like scene texture (thesis §5.5): on
  // servo datasets those that stay put while the sheet sweeps
  // (laser/sweep_filter.h), with a fixed laser those that move with the
  // scene as the platform moves (laser/motion_filter.h).
  bool texture_filter = true;
  // Fixed laser: the motion filter matches earlier candidates along their
  // epipolar curves (thesis §5.5) before falling back to the profile's depth.
  bool epipolar_texture = true;
  // Drop line detections on an albedo edge, judged in the flood-lit channel
  // (laser::DetectorOptions::albedo_channel; red for a green laser).
  bool drop_albedo_edges = true;
  // Drop line segments whose third colour shows too little of the laser's
  // share of light (laser::DetectorOptions::min_signature_share; flood-lit
  // marine snow).
  bool drop_off_colour = true;
  // Search each scan line for the line only within this many pixels of
  // where the frame before had it (laser::DetectorOptions::line_prior);
  // whole scan lines where it had none, in every
  // LineStage::kWholeScanEvery-th frame, and again when a point turns up
  // off that line; 0: every scan line whole. Servo sweeps and fixed
  // lasers without the motion filter only (that filter judges the
  // candidates of whole scan lines).
  int line_window_px = laser::DetectorOptions{}.line_window_px;
  // Drop line points whose camera ray grazes the light sheet: a pixel of
  // detection error would move them by more than this fraction of their
  // range (laser::TriangulateProfile; 0 = keep all).
  double max_range_error_per_px = laser::kMaxRangeErrorPerPixel;
  // Interleaved datasets (frames.csv laser_on): detect the line in the
  // difference of each laser-on frame and the laser-off frame before it.
  bool detect_on_difference = true;
  // Several-camera datasets (sim --pods 2): the profiles of the further
  // cameras (images in DATASET/NAME/) join the cloud, placed with the main
  // camera's poses through the rig; only without --camera.
  bool other_cameras = true;
  int max_frames = 0;  // 0: all
  // 16-bit frames holding samples of this many bits in their low bits
  // (ScaleLowBitSamples; 9-16, 16: as stored).
  int sample_bits = 16;
  bool quiet = false;
  // Diagnostics on simulated datasets: the odometry's features take their
  // depth from the simulator's true scene (scene.yaml, groundtruth.tum)
  // instead of the laser surface (fusion::SimulatorTruth).
  bool oracle_depths = false;
  // Diagnostics on simulated datasets: the odometry's feature tracks are
  // moved to where the simulator's true scene point of each projects.
  bool oracle_tracks = false;
  // Passes of the self-referenced odometry over the frames. In a later
  // pass the features take their depths from the surface the pass before
  // measured over the whole scan, from the first frame on
  // (SelfReferencedOptions::prior_surface), not from what the laser has
  // swept so far: for a scene with a surface in front of its main one (a
  // shaft before a hull), whose depth the first pass had to guess until the
  // laser reached it. The second pass's surface is placed with poses that
  // had those depths from the start, so a third pass starts from a truer
  // one, and so on until the trajectory settles. 0 (auto): when the first
  // pass found such a surface (SurfaceModel::HasFrontSurface), at least
  // kMinAutoPasses, then more while the last one moved the trajectory by
  // passes_settled_m or passes_settled_deg or more (rms over the frames)
  // and, from the fourth on, by less than passes_converging_ratio of the
  // move before (else more would only shuffle it), at most kMaxPasses
  // (BENCHMARKS.md, "Passes until the trajectory settles"); else one. 1 to
  // kMaxPasses: so many. Each pass costs the time of the first; the last
  // one's outputs replace the others'.
  int passes = 0;
  static constexpr int kMinAutoPasses = 3;
  static constexpr int kMaxPasses = 6;
  double passes_settled_m = 0.002;  // as the start's refinements settle
  double passes_settled_deg = 0.05;
  double passes_converging_ratio = 0.7;
  // A first pass whose start had not settled (faint, noisy features:
  // turbid water; with a fixed laser, whose held frames span the
  // platform's own motion, or a surface in front, only a start far from
  // settled) on a tracked image 640 px wide or more is run again tracking
  // half of it, which averages more of the sensor's noise in each KLT
  // window (ReconstructReport::SmallerTrackingWidth; BENCHMARKS.md,
  // "Turbid water, measured again", "Turbid hovers: a start still moving
  // runs again on half the image"), if no more passes follow (a hull's
  // shaft needs the full image). The CLI turns it off when
  // --max-tracking-width is given.
  bool retry_smaller_tracking = true;
  // The odometry tracks every Nth frame once running and places the frames
  // between between them (SelfReferencedOptions::track_every, which this
  // sets). 0 (auto): the fewest N that keep the tracked rate at or below
  // kMaxTrackedRateHz, from frames.csv's timestamps: 2 at the thesis
  // camera's 144 Hz (a hover's motion is smooth over 14 ms: the tank
  // hovers' clouds stay within the seeds' spread, and the scan runs in real
  // time on two cores, BENCHMARKS.md), 1 at 100 Hz and below.
  int track_every = 0;
  static constexpr double kMaxTrackedRateHz = 100.0;
  // Once a start attempt has been refused because its held profiles were
  // too narrow for the plane, each later attempt's first tracking of the
  // held frames takes every Nth only
  // (SelfReferencedOptions::start_screen_every, which this sets). 0 (auto):
  // the fewest N, and at least track_every, that keep that tracked rate at
  // or below kMaxStartScreenRateHz: 4 at 144 Hz (36 Hz), 2 at 50 Hz
  // (BENCHMARKS.md, "The refused starts screened at 36 Hz").
  int start_screen_every = 0;
  static constexpr double kMaxStartScreenRateHz = 40.0;
  // The odometry's windowed BA on a second thread
  // (vo::OdometryOptions::async_bundle_adjustment, which this sets); unset
  // (auto): when the frames come faster than vo::kAsyncBundleAdjustmentAboveHz,
  // where a keyframe's BA holds up several frames and the scan would fall behind
  // real time (the 144 Hz tank scan: real-time factor 0.99-1.13 -> 1.06-1.22
  // on two cores, its clouds within the seeds' spread, BENCHMARKS.md).
  std::optional<bool> async_bundle_adjustment;
  // The poses' smoothing over +-N frames (SelfReferencedOptions::
  // smoothing_half_window, which this sets); unset (auto): that option's
  // 10 frames, but no more than kSmoothingMaxHalfSpanS, from frames.csv's
  // timestamps: 10 at 72 Hz and above (69 ms at the thesis camera's 144 Hz),
  // 7 at the hulls' 50 Hz, 4 at 28.8 Hz, 2 at 14.4 Hz. Over longer spans the
  // quadratic fit flattens a hover's turns: over 0.2 s the simulator's true
  // hover came out 0.3-0.5 % small, and the tank scans at 14.4-48 Hz 0.2-
  // 0.5 % small, their board's distance error half as large again
  // (BENCHMARKS.md, "The pose smoothing over 0.14 s").
  std::optional<int> smoothing_half_window;
  static constexpr double kSmoothingMaxHalfSpanS = 0.14;
  // The frames replayed as a live camera delivers them (FrameReader's
  // live_from): frame i is read no sooner than its timestamp's offset from
  // the first's after the run began, so the processing cannot work ahead
  // of the camera, and each frame's lag behind it is measured
  // (ReconstructReport::live_lag; `uwscan bench pipeline --live`). A live
  // scan is processed once: it needs one pass and no retry on half the
  // image.
  bool live = false;
  // A live run that falls further than this behind the camera drops
  // frames to catch up, as a live system on a machine slower than its
  // camera must (FrameReader's max_lag_s; ReconstructReport::
  // frames_dropped_live); unset: every frame processed, however late.
  std::optional<double> live_max_lag_s;
  void Check() const;
};

// How far a live run's cloud fell behind the camera
// (ReconstructJob::live): each placed frame's lag is the time from its
// delivery (its timestamp's offset from the first frame's) to its profile
// joining the cloud, which includes waiting for the pose smoothing's later
// frames.
struct LiveLag {
  double max_s = 0.0;
  double max_at_scan_s = 0.0;  // the delivery time (from the first frame) of the frame
  double median_s = 0.0;
  double last_s = 0.0;  // of the last frame placed (at the scan's end)
  // At each whole second of the scan (1 s, 2 s, ...), the lag of the last
  // frame delivered by then among those placed; null where none was.
  std::vector<std::optional<double>> at_each_second_s;
  nlohmann::json ToJson() const;
};
// The summary of a live run's lags: (delivery time from the first frame,
// lag) of each placed frame, of every camera, in any order; none if no
// frame was placed.
std::optional<LiveLag> SummarizeLiveLag(std::vector<std::pair<double, double>> lags,
                                        double sequence_duration_s);

// A further camera of the rig whose profiles joined the cloud.
struct CameraReport {
  std::string name, laser;
  int frames = 0;
  int frames_with_line = 0;
  int frames_without_pose = 0;  // outside the main camera's trajectory
  int frames_dropped_live = 0;  // as ReconstructReport's, not counted in `frames`
  long points = 0;
  nlohmann::json ToJson() const;
};

struct ReconstructReport {
  int frames = 0;
  int frames_with_line = 0;
  int frames_laser_off = 0;      // interleaved scans: frames taken with the laser off
  int frames_on_difference = 0;  // line detected in the difference to the laser-off frame
  int frames_without_pose = 0;
  long points = 0;
  long points_uncompensated = 0;
  long triangulation_failures = 0;  // line points whose ray missed the light sheet
  // Many of the first frame's line points missed the sheet, and with the
  // inverse of the laser's pose in rig.yaml all would meet it.
  bool laser_pose_inverse_fits = false;
  // Interleaved scans: the frame marked laser-off in which the line showed
  // against the laser-on frame before it (frames.csv's laser_on inverted);
  // -1 if none.
  int laser_on_inverted_at = -1;
  // The first frame with the laser on showed the line in another colour
  // than rig.yaml's wavelength gives: that colour's name, and what to do
  // (laser::LaserColourWarning); empty if not.
  std::string laser_seen_in, laser_colour_warning;
  long static_detections_removed = 0;  // line candidates ignored by the sweep filter
  // Fixed laser: earlier candidates placed on the scene by an epipolar
  // match with a frame before them (the rest take the profile's depth).
  long texture_epipolar_matches = 0;
  bool line_ranges = false;     // whether the odometry used them
  bool laser_sweeps = false;    // a servo sweeps the laser (else it is fixed on the platform)
  double contrast_scale = 0.0;  // the odometry's, as used (ReconstructJob::contrast_scale)
  double log_offset = 0.0;      // SelfReferencedOptions::log_offset_fraction, as used
  long albedo_edge_points = 0;  // line points dropped on an albedo edge
  // Line candidates dropped for their colour (ReconstructJob::drop_off_colour),
  // and the frames with such a segment.
  long off_colour_points = 0;
  int frames_with_off_colour = 0;
  // Line points whose ray grazes the sheet, and the limit as used
  // (ReconstructJob::max_range_error_per_px).
  long grazing_points = 0;
  double max_range_error_per_px = 0.0;
  int frames_with_static_detections = 0;  // ... on >= 5 % of the scan lines
  // The scene at full scale in the laser's colour away from the line
  // (laser::MeasureClipping, frames with the laser on): samples, of how
  // many looked at, and the frames (of every camera) looked at and those
  // with at least laser::kClippedFrameShare of it. There the line cannot
  // stand out: lost, or texture taken for it.
  long clipped_samples = 0;
  long clipping_samples_examined = 0;
  int frames_clipping_examined = 0;
  int frames_with_clipped_scene = 0;
  // The same in the features' colour, the one the self-referenced odometry
  // tracks (fusion::SelfReferencedPoseProvider::PassiveColour; colour
  // cameras only), and the frames with at least
  // laser::kClippedFeaturesFrameShare of it: the texture is lost there.
  long features_clipped_samples = 0;
  long features_clipping_samples_examined = 0;
  int frames_features_clipping_examined = 0;
  int frames_with_clipped_features = 0;
  std::string features_colour;           // its name ("red"); empty: not measured
  int frames_sweep_filter_restored = 0;  // nearly the whole line would have gone: kept
  FrameDoubts first_frame;               // the main camera's (LineStage's first)
  int sample_bits = 16;                  // as used (ReconstructJob::sample_bits)
  double seconds = 0.0;
  double seconds_detect = 0.0, seconds_triangulate = 0.0, seconds_pose = 0.0, seconds_io = 0.0;
  // Of seconds_io: waiting for the reading thread's next image (read,
  // decoded, its line found ahead); a disk slower than the processing
  // shows here.
  double seconds_waiting_for_images = 0.0;
  // As used (ReconstructJob::line_window_px; 0: whole scan lines), and the
  // frames with a point off the windows' line, detected again whole.
  int line_window_px = 0;
  int frames_line_window_redone = 0;
  int passes = 1;  // the self-referenced odometry's (ReconstructJob::passes)
  // How far each pass after the first moved the trajectory from the pass
  // before's (rms over the frames both placed).
  std::vector<fusion::PoseChange> pass_changes;
  // Auto passes: whether the last one's move was within the tolerance
  // (ReconstructJob::passes_settled_m, _deg); unset with one pass or a
  // forced count.
  std::optional<bool> passes_settled;
  fusion::PoseChange passes_settled_within;
  // The self-referenced odometry's surface had one standing in front of the
  // scene's main one (a shaft before a hull; SurfaceModel::HasFrontSurface),
  // whose features it had to give the main one's depth until the laser
  // reached it: what auto passes run again for (warned of when one pass
  // ran: --live, --passes 1).
  bool surface_in_front = false;
  int track_every = 1;  // the odometry's, as used (ReconstructJob::track_every)
  // The refused starts' screens, as used (ReconstructJob::start_screen_every).
  int start_screen_every = 1;
  bool async_bundle_adjustment = false;  // as used (ReconstructJob::async_bundle_adjustment)
  int smoothing_half_window = 0;         // as used (ReconstructJob::smoothing_half_window)
  double seconds_earlier_passes = 0.0;   // of the passes before the last (included in `seconds`)
  // The tracked image's width of a first attempt run again at half of it
  // (ReconstructJob::retry_smaller_tracking), and how far that attempt's
  // start still moved (mm rms); 0 if none.
  int tracking_retried_from_width = 0;
  double retried_start_change_mm = 0.0;
  // Why such a second run failed, whose outputs are then the first's.
  std::string tracking_retry_failed;
  // Why the pass after the last one here failed or was interrupted (its
  // error), whose outputs are then this pass's: each pass commits its own
  // whole.
  std::string later_pass_failed;
  double sequence_duration_s = 0.0;  // from the frame timestamps
  std::optional<LiveLag> live_lag;   // ReconstructJob::live only
  // Frames a live run dropped to keep within ReconstructJob::live_max_lag_s
  // of the camera (not counted in `frames`), and that limit; -1 unset.
  int frames_dropped_live = 0;
  double live_max_lag_s = -1.0;
  FrameGaps frame_gaps;  // frames the camera or its recorder dropped (frames.csv)
  std::string pose_source;
  // --poses: the file's poses' median step (s) and how many lie within the
  // frames' times; -1 without such a file.
  double external_pose_step_s = -1.0;
  int external_poses_in_scan = -1;
  nlohmann::json pose_details;  // statistics of the pose provider
  std::vector<CameraReport> other_cameras;

  int scan_lines = 0;  // image rows (or columns) the detector scans: a full profile's points
  double RealTimeFactor() const { return seconds > 0 ? sequence_duration_s / seconds : 0.0; }
  double ClippedSceneShare() const {
    return clipping_samples_examined > 0
               ? static_cast<double>(clipped_samples) / clipping_samples_examined
               : 0.0;
  }
  double ClippedFeaturesShare() const {
    return features_clipping_samples_examined > 0
               ? static_cast<double>(features_clipped_samples) / features_clipping_samples_examined
               : 0.0;
  }
  // What degraded the result and why, for the user (also in report.json):
  // frames without a laser line, short profiles, frames without pose,
  // tracking losses, rejected poses.
  std::vector<std::string> Warnings() const;
  // Half the odometry's tracked image width if its start had not settled
  // (on a servo sweep of a scene with no surface in front, its poses still
  // moving by more than their tolerance; else by more than ten times it)
  // and that half is at least 320 px (the narrowest it tracks); none
  // otherwise.
  std::optional<int> SmallerTrackingWidth() const;
  nlohmann::json ToJson() const;
};

// --poses-body-from-camera's value: "tx,ty,tz,qx,qy,qz,qw" (TUM's order),
// a unit quaternion (to 1e-3; normalised); else a UsageError.
Rigid3d ParseBodyFromCamera(const std::string& value);
// --track-every's (or `flag`'s) value: "auto" (0) or a count >= 1; else a
// UsageError that names the flag.
int ParseTrackEvery(const std::string& value, const std::string& flag = "--track-every");
// --contrast-scale's value: "auto" (unset) or a fraction in [0, 0.5]; else
// a UsageError.
std::optional<double> ParseContrastScale(const std::string& value);
// ReconstructJob::track_every for these frames, auto resolved from their
// timestamps.
int ResolveTrackEvery(int track_every, const std::vector<FrameRecord>& frames);
// ReconstructJob::start_screen_every for these frames, auto resolved from
// their timestamps and the resolved track_every.
int ResolveStartScreenEvery(int start_screen_every, int track_every,
                            const std::vector<FrameRecord>& frames);
// --smoothing-half-window's value: "auto" (unset) or a count >= 0; else a
// UsageError.
std::optional<int> ParseSmoothingHalfWindow(const std::string& value);
// --max-start-plane-angle's value (deg, in (0, 90]) as
// SelfReferencedOptions::min_start_plane_view_cosine (90: any plane, 0);
// else a UsageError.
double StartPlaneViewCosine(double max_angle_deg);
// The angle of SelfReferencedOptions' default, --max-start-plane-angle's.
double DefaultMaxStartPlaneAngleDeg();
// ReconstructJob::smoothing_half_window for these frames, auto resolved
// from their timestamps (without time between them: 10).
int ResolveSmoothingHalfWindow(std::optional<int> half_window,
                               const std::vector<FrameRecord>& frames);
// ReconstructJob::async_bundle_adjustment for these frames, auto resolved
// from their timestamps.
bool ResolveAsyncBundleAdjustment(std::optional<bool> async,
                                  const std::vector<FrameRecord>& frames);

// The image files RunReconstruct reads for `job`: the main camera's, then
// those of the further cameras it uses (after the same checks: a missing
// folder, file or image is named).
std::vector<std::filesystem::path> ReconstructImages(const ReconstructJob& job);

// Uses `provider` if given, else the job's --poses file, else the
// self-referenced visual odometry. Writes OUT/cloud.ply,
// OUT/cloud_uncompensated.ply, OUT/trajectory.tum and OUT/report.json.
ReconstructReport RunReconstruct(const ReconstructJob& job,
                                 std::unique_ptr<fusion::PoseProvider> provider = nullptr);

}  // namespace uwscan
