// uwscan reconstruct: the self-referenced scan of a dataset.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <string>

#include "commands.h"
#include "uwscan/pipeline/reconstruct.h"
#include "uwscan/util/error.h"

namespace uwscan::cli {

namespace {

// " in three passes ..." for the summary line; nothing for one pass.
std::string PassesNote(int passes, bool automatic) {
  static const char* const kCounts[] = {"two", "three", "four", "five", "six"};
  if (passes <= 1) return "";
  const std::string count = passes - 2 < static_cast<int>(std::size(kCounts))
                                ? kCounts[passes - 2]
                                : std::to_string(passes);
  return " in " + count + " passes" + (automatic ? " (a surface in front of the main one)" : "");
}

// ", tracking the mean of every 2 frames" for the summary line
// (SelfReferencedOptions::average_skipped_frames); nothing for every frame.
std::string TrackEveryNote(int every) {
  if (every <= 1) return "";
  return ", tracking the mean of every " + std::to_string(every) + " frames";
}

// --smoothing-half-window's help, from the values ResolveSmoothingHalfWindow
// uses, so that it cannot fall out of step with them.
std::string SmoothingHelp() {
  const int frames = fusion::SelfReferencedOptions().smoothing_half_window;
  const double span_s = ReconstructJob::kSmoothingMaxHalfSpanS;
  auto at = [&](int rate_hz) {
    return std::to_string(std::min<long>(frames, std::lround(span_s * rate_hz))) + " at " +
           std::to_string(rate_hz) + " Hz";
  };
  char span[32];
  std::snprintf(span, sizeof(span), "%g", span_s);
  return "poses smoothed over +-N frames (quadratic fit), output N frames late (0 = raw); auto: " +
         std::to_string(frames) + ", but at most the frames within " + span + " s on each side (" +
         at(30) + ", " + at(15) + ")";
}

}  // namespace

void RegisterReconstructCommand(CLI::App& app) {
  auto job = std::make_shared<ReconstructJob>();
  auto dataset = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  auto poses = std::make_shared<std::string>();
  auto no_compensation = std::make_shared<bool>(false);
  auto keep_static = std::make_shared<bool>(false);
  auto no_epipolar = std::make_shared<bool>(false);
  auto no_difference = std::make_shared<bool>(false);
  auto no_line_ranges = std::make_shared<bool>(false);
  auto line_ranges = std::make_shared<bool>(false);
  auto keep_albedo_edges = std::make_shared<bool>(false);
  auto keep_off_colour = std::make_shared<bool>(false);
  auto passes = std::make_shared<std::string>("auto");
  auto track_every = std::make_shared<std::string>("auto");
  auto start_screen_every = std::make_shared<std::string>("auto");
  auto smoothing_half_window = std::make_shared<std::string>("auto");
  auto max_start_plane_angle = std::make_shared<double>(DefaultMaxStartPlaneAngleDeg());
  auto contrast_scale = std::make_shared<std::string>("auto");
  auto main_camera_only = std::make_shared<bool>(false);
  auto* cmd = app.add_subcommand(
      "reconstruct",
      "Motion-compensated point cloud from a dataset: cloud.ply, cloud_uncompensated.ply, "
      "trajectory.tum, report.json");
  cmd->add_option("--dataset", *dataset, "dataset folder (rig.yaml, frames.csv, frames/)")
      ->required();
  cmd->add_option("--out", *out, "output folder")->required();
  cmd->add_option("--poses", *poses, "external trajectory (TUM, world_from_camera) instead of VO");
  cmd->add_option("--poses-time-offset", job->poses_time_offset_s,
                  "seconds added to the --poses file's timestamps to put them on the camera's "
                  "clock (an INS logging on its own clock)");
  auto body_from_camera = std::make_shared<std::string>();
  cmd->add_option("--poses-body-from-camera", *body_from_camera,
                  "the --poses file gives a body's poses (an INS's), not the camera's: the "
                  "camera's pose in that body's frame, tx,ty,tz,qx,qy,qz,qw (metres; TUM's order)");
  cmd->add_flag("--no-motion-compensation", *no_compensation,
                "place every profile with the first pose (cloud.ply too)");
  cmd->add_option("--camera", job->camera_name,
                  "camera name (default: the first; its images are in DATASET/frames.csv)");
  cmd->add_flag("--main-camera-only", *main_camera_only,
                "several-camera datasets: leave out the further cameras' profiles (images in "
                "DATASET/NAME/; by default they join the cloud, placed with the main camera's "
                "poses through the rig)");
  cmd->add_option("--laser", job->laser_name, "laser name (default: the first)");
  cmd->add_option("--max-frames", job->max_frames, "process only the first N frames (0 = all)");
  AddSampleBitsOption(cmd, &job->sample_bits);
  cmd->add_flag("--keep-static-detections", *keep_static,
                "keep line candidates that behave like scene texture (removed by default, "
                "thesis §5.5: on servo scans those that stay put while the laser sweeps, with a "
                "fixed laser those that move with the scene; a painted stripe or reflection)");
  cmd->add_flag("--no-epipolar-texture", *no_epipolar,
                "fixed laser: place earlier line candidates at the laser profile's depth only, "
                "without matching them along their epipolar curves with a frame before (for "
                "comparison)");
  cmd->add_flag("--keep-albedo-edges", *keep_albedo_edges,
                "keep line points on an albedo edge (dropped by default: the edge pulls the "
                "sub-pixel fit towards its bright side; judged in the flood-lit colour channel)");
  cmd->add_flag(
      "--keep-off-colour", *keep_off_colour,
      "keep line candidates whose third colour (blue beside a green laser) shows less "
      "than " +
          std::to_string(std::lround(100 * laser::DetectorOptions{}.min_signature_share)) +
          " % of the laser's share of light (dropped by default: spots lit by the "
          "floods, such as marine snow near the lights)");
  cmd->add_option("--line-window", job->line_window_px,
                  "search each image row (or column) for the laser line only within this many "
                  "pixels of where the frame before had it; whole rows where it had none, in "
                  "every 10th frame, and again when something appears off that line (0 = every "
                  "row whole; not with a fixed laser's motion filter)")
      ->capture_default_str();
  cmd->add_option("--max-range-error-per-px", job->max_range_error_per_px,
                  "drop line points whose camera ray grazes the light sheet, so that one pixel "
                  "of detection error would move them by more than this fraction of their range "
                  "(something lit far from the line, carried by its ray to where it meets the "
                  "sheet tens of metres away; 0 = keep all)")
      ->capture_default_str();
  cmd->add_option("--max-dormant-frames", job->self_referenced.odometry.tracker.max_dormant_frames,
                  "frames a feature track cut by the laser line may stay lost and still be taken "
                  "up again under its id (thesis §5.5; 0 = off)")
      ->capture_default_str();
  CLI::Option* tracking_width =
      cmd->add_option("--max-tracking-width", job->self_referenced.max_tracking_width,
                      "the odometry tracks the image halved until it is at most this wide, but "
                      "not below 160 px (0 = full resolution); not given, a one-pass run whose "
                      "start does not settle (turbid water) runs again tracking half the image")
          ->capture_default_str();
  cmd->add_option("--track-every", *track_every,
                  "the odometry tracks every Nth frame once running; the frames between get "
                  "poses interpolated between the tracked ones; auto: every frame up to 100 Hz, "
                  "every second at 101-200 Hz, ...")
      ->capture_default_str();
  cmd->add_option("--start-screen-every", *start_screen_every,
                  "once a start attempt is refused because its held profiles are too narrow for "
                  "the plane, the later ones first track every Nth frame held (a screen), then as "
                  "--track-every; auto: at most 40 per second and at least --track-every (every "
                  "4th at 144 Hz)")
      ->capture_default_str();
  cmd->add_option("--contrast-scale", *contrast_scale,
                  "equalise the tracked image's contrast over a Gaussian of this fraction of its "
                  "width (the lights travel with the camera; 0 = off); auto: 0.05 with a fixed "
                  "laser (the platform's motion scans), 0 on servo sweeps (hovering)")
      ->capture_default_str();
  cmd->add_option("--log-offset", job->self_referenced.log_offset_fraction,
                  "track the image in logarithm, log(I + this x its mean): the lights' gain "
                  "across a patch becomes an offset the high pass removes (0 = linear)")
      ->capture_default_str();
  cmd->add_option("--window", job->self_referenced.odometry.ba.window_size,
                  "keyframes in the odometry's windowed bundle adjustment")
      ->capture_default_str();
  cmd->add_option("--ba-history", job->self_referenced.odometry.ba.history_keyframes,
                  "keyframes before the window whose rays of its points enter the BA, held")
      ->capture_default_str();
  cmd->add_option("--smoothing-half-window", *smoothing_half_window, SmoothingHelp())
      ->capture_default_str();
  cmd->add_option("--init-refinements", job->self_referenced.init_refinements,
                  "times the frames held at the start are at least tracked and their laser "
                  "profiles placed again with those poses before the scan goes on (0 = once, "
                  "with the guessed motion)")
      ->capture_default_str();
  cmd->add_option("--max-init-refinements", job->self_referenced.max_init_refinements,
                  "... and at most, while their poses still move (> 2 mm rms) and converge")
      ->capture_default_str();
  cmd->add_option("--max-start-plane-angle", *max_start_plane_angle,
                  "deg: the scan starts only on a plane it sees within this angle of the plane's "
                  "normal (a start on a plane through the camera, from a slow sweep's profiles "
                  "placed with too little motion, comes out many times too large); 90 = any")
      ->capture_default_str();
  cmd->add_flag("--no-difference-image", *no_difference,
                "interleaved scans: detect the line in the laser-on frame itself, not in its "
                "difference to the laser-off frame before it");
  cmd->add_flag("--no-line-ranges", *no_line_ranges,
                "scale only from the accumulated laser surface, not also from the map points "
                "the laser line meets in each keyframe (thesis §5.4); by default they are used "
                "with a fixed laser and not on servo sweeps");
  cmd->add_flag("--line-ranges", *line_ranges,
                "use the map points the laser line meets in each keyframe on servo sweeps too");
  cmd->add_option("--ba-time-limit", job->self_referenced.odometry.ba.max_solver_time_s,
                  "seconds one windowed BA may take before it stops unconverged")
      ->capture_default_str();
  AddAsyncBundleAdjustmentFlags(
      cmd, &job->async_bundle_adjustment,
      "the odometry's windowed BA on a second thread, its result joining the map 8 tracked "
      "frames later; by default above 100 Hz (the scan keeps up with the camera)");
  cmd->add_option("--passes", *passes,
                  "passes of the odometry over the frames (1-6): in a later one the features take "
                  "their depths from the surface the pass before measured over the whole scan "
                  "(each pass the time of the first; for a surface in front of the main one, "
                  "e.g. a shaft before a hull); auto: when the first found such a surface, three "
                  "and more until the trajectory settles (moves by less than 2 mm and 0.05 deg "
                  "rms; at most 6), else one")
      ->capture_default_str();
  cmd->add_flag("--oracle-depths", job->oracle_depths,
                "diagnostics on simulated datasets: the odometry's features take their depth "
                "from the simulator's true scene instead of the laser surface (what the "
                "odometry does with a perfect depth model)");
  cmd->add_flag("--oracle-tracks", job->oracle_tracks,
                "diagnostics on simulated datasets: each feature track is moved in every frame "
                "to where the simulator's true scene point at its first pixel projects (what the "
                "odometry does with perfect tracks)");
  cmd->add_flag("--live", job->live,
                "replay the frames at the camera's pace, as a live camera delivers them, and "
                "report how far the cloud fell behind it (report.json's live_lag_s); one pass, "
                "no retry on half the image");
  auto live_max_lag = std::make_shared<double>(0.0);
  cmd->add_option("--live-max-lag", *live_max_lag,
                  "with --live: drop frames whenever the processing falls more than this many "
                  "seconds behind the camera, as a live system slower than its camera must "
                  "(report.json's frames_dropped_live); by default none is dropped");
  cmd->add_flag("--quiet", job->quiet, "no progress bar or summary");
  cmd->callback([=] {
    job->dataset = *dataset;
    job->out = *out;
    if (!poses->empty()) job->poses_file = *poses;
    if (!body_from_camera->empty())
      job->poses_body_from_camera = ParseBodyFromCamera(*body_from_camera);
    job->motion_compensation = !*no_compensation;
    job->texture_filter = !*keep_static;
    job->epipolar_texture = !*no_epipolar;
    job->drop_albedo_edges = !*keep_albedo_edges;
    job->drop_off_colour = !*keep_off_colour;
    job->detect_on_difference = !*no_difference;
    if (*no_line_ranges && *line_ranges) {
      throw UsageError("--line-ranges and --no-line-ranges exclude each other");
    }
    if (*no_line_ranges) job->line_ranges = false;
    if (*line_ranges) job->line_ranges = true;
    job->other_cameras = !*main_camera_only;
    const int count = passes->size() == 1 ? (*passes)[0] - '0' : -1;
    if (job->live && *passes == "auto") {
      job->passes = 1;  // processed once, as it comes
    } else if (*passes == "auto") {
      job->passes = 0;
    } else if (count >= 1 && count <= ReconstructJob::kMaxPasses) {
      job->passes = count;
    } else {
      throw UsageError("--passes must be auto or 1 to " +
                       std::to_string(ReconstructJob::kMaxPasses) + ", got '" + *passes + "'");
    }
    job->track_every = ParseTrackEvery(*track_every);
    job->start_screen_every = ParseTrackEvery(*start_screen_every, "--start-screen-every");
    job->smoothing_half_window = ParseSmoothingHalfWindow(*smoothing_half_window);
    job->self_referenced.min_start_plane_view_cosine = StartPlaneViewCosine(*max_start_plane_angle);
    job->retry_smaller_tracking = tracking_width->count() == 0 && !job->live;
    if (cmd->count("--live-max-lag") > 0) job->live_max_lag_s = *live_max_lag;
    job->contrast_scale = ParseContrastScale(*contrast_scale);
    const ReconstructReport r = RunReconstruct(*job);
    if (!job->quiet) {
      std::fprintf(stderr,
                   "reconstruct: %d frames (%d with a laser line, %d without pose), %ld points, "
                   "poses from %s%s%s, %.1f s (%.2fx real time) -> %s/cloud.ply\n",
                   r.frames, r.frames_with_line, r.frames_without_pose, r.points,
                   r.pose_source.c_str(), PassesNote(r.passes, job->passes == 0).c_str(),
                   (TrackEveryNote(r.track_every) +
                    (r.async_bundle_adjustment ? ", windowed BA on its own thread" : ""))
                       .c_str(),
                   r.seconds, r.RealTimeFactor(), out->c_str());
      if (r.live_lag) {
        std::fprintf(
            stderr,
            "reconstruct: live, the cloud %.2f s behind the camera at the end (at most "
            "%.2f s, median %.2f s)%s\n",
            r.live_lag->last_s, r.live_lag->max_s, r.live_lag->median_s,
            r.frames_dropped_live > 0
                ? (", " + std::to_string(r.frames_dropped_live) + " frames dropped").c_str()
                : "");
      }
      // (A live run waits for the camera's frames by design.)
      if (!r.live_lag && r.seconds > 1.0 && r.seconds_waiting_for_images > 0.25 * r.seconds) {
        std::fprintf(stderr,
                     "reconstruct: %.1f s of the %.1f s went waiting for the next image to be "
                     "read and decoded: a disk slower than the processing shows here\n",
                     r.seconds_waiting_for_images, r.seconds);
      }
      for (const CameraReport& camera : r.other_cameras) {
        std::fprintf(stderr,
                     "reconstruct: camera %s with %s: %d frames (%d with a line), %ld points\n",
                     camera.name.c_str(), camera.laser.c_str(), camera.frames,
                     camera.frames_with_line, camera.points);
      }
    }
    for (const std::string& warning : r.Warnings())
      std::fprintf(stderr, "reconstruct: warning: %s\n", warning.c_str());
  });
}

}  // namespace uwscan::cli
