// The reconstruction job's report as JSON and warnings.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "uwscan/io/image.h"
#include "uwscan/laser/clipping.h"
#include "uwscan/laser/profile.h"
#include "uwscan/pipeline/reconstruct.h"
#include "uwscan/util/json.h"
#include "uwscan/util/statistics.h"

namespace uwscan {

namespace {

// A start whose poses still move by more than this many times the
// tolerance they settle within did not hold the scene still, and the whole
// trajectory may be off (BENCHMARKS.md, "Turbid water, measured again").
constexpr double kFarFromSettled = 10.0;

// How far the start's poses still moved and turned at its last measured
// refinement (none if no refinement tracked a held frame the one before
// had) and the tolerances they settle within, if they had not settled.
struct UnsettledStart {
  std::optional<double> moved_mm, turned_deg;
  double within_mm = 0.0, within_deg = 0.0;
  bool Moving() const { return moved_mm && *moved_mm > within_mm; }
  bool Far() const { return moved_mm && *moved_mm > kFarFromSettled * within_mm; }
};
std::optional<UnsettledStart> FindUnsettledStart(const nlohmann::json& pose_details) {
  if (!pose_details.is_object()) return std::nullopt;
  const auto settled = pose_details.find("start_settled");
  if (settled == pose_details.end() || !settled->is_boolean() || settled->get<bool>())
    return std::nullopt;
  return UnsettledStart{NumberAt(pose_details, "start_last_change_mm"),
                        NumberAt(pose_details, "start_last_change_deg"),
                        NumberAt(pose_details, "start_settled_within_mm").value_or(2.0),
                        NumberAt(pose_details, "start_settled_within_deg").value_or(0.05)};
}

}  // namespace

std::optional<int> ReconstructReport::SmallerTrackingWidth() const {
  const std::optional<UnsettledStart> start = FindUnsettledStart(pose_details);
  const int half = pose_details.is_object() ? pose_details.value("tracked_image_width", 0) / 2 : 0;
  if (!start || half < 320) return std::nullopt;
  // On a servo sweep the platform hovers while the frames are held: a
  // start still moving is the tracks' noise (turbid water), which half the
  // image averages (BENCHMARKS.md, "Turbid hovers: a start still moving
  // runs again on half the image"). With a fixed laser the held frames
  // span the platform's own motion, and a start a few millimetres from
  // settled is not the tracks' doing (a short transect came out worse on
  // half the image); a surface in front of the main one (a shaft before a
  // hull) needs the full image. There only a start far from settled runs
  // again.
  const bool hover = laser_sweeps && !surface_in_front;
  if (!(hover ? start->Moving() : start->Far())) return std::nullopt;
  return half;
}

std::vector<std::string> ReconstructReport::Warnings() const {
  // How the frames are read (a black frame, a mosaic taken for mono, ...)
  // first: it explains what follows.
  std::vector<std::string> warnings = first_frame.Warnings();
  const auto percent = [](double part, double whole) {
    return std::to_string(static_cast<int>(std::lround(100.0 * part / std::max(whole, 1.0))));
  };
  if (!laser_colour_warning.empty()) warnings.push_back(laser_colour_warning);
  if (laser_on_inverted_at >= 0) {
    warnings.push_back(fmt::format(
        "frames.csv's laser_on column looks inverted: frame {}, marked laser off, shows the line "
        "against the frame before it, marked on (1 marks the frames taken with the laser on)",
        laser_on_inverted_at));
  }
  const int frames_lit = frames - frames_laser_off;
  if (frames_lit > 0 && frames_with_line < 0.9 * frames_lit) {
    warnings.push_back("no laser line in " + percent(frames_lit - frames_with_line, frames_lit) +
                       " % of the frames with the laser on (turbid or dark water, the line out "
                       "of view or too weak): those frames add nothing to the cloud");
  }
  const std::string missed = laser::MissedSheetWarning(
      triangulation_failures, points + grazing_points, laser_pose_inverse_fits);
  if (!missed.empty()) warnings.push_back(missed);
  const std::string slow = SlowFramesWarning(frame_gaps, "frames.csv");
  if (!slow.empty()) warnings.push_back(slow);
  if (frame_gaps.missing > 0) {
    warnings.push_back(fmt::format(
        "{} frame(s) missing from the sequence ({} gap(s) in frames.csv's timestamps, the longest "
        "{:.0f} ms): the camera or its recorder dropped them; the cloud has no profiles there, "
        "and the odometry tracks across each gap (more motion between its frames: a long gap "
        "may lose the tracks)",
        frame_gaps.missing, frame_gaps.gaps, 1e3 * frame_gaps.longest_s));
  }
  std::string others_dropped;  // the further cameras' drops, if any
  for (const auto& camera : other_cameras) {
    if (camera.frames_dropped_live == 0) continue;
    others_dropped += fmt::format(
        "{} {} of camera {}'s ({} %)", others_dropped.empty() ? "; and" : ",",
        camera.frames_dropped_live, camera.name,
        percent(camera.frames_dropped_live, camera.frames + camera.frames_dropped_live));
  }
  if (frames_dropped_live > 0 || !others_dropped.empty()) {
    warnings.push_back(fmt::format(
        "{} frame(s) ({} %) dropped to keep the live cloud within {:g} s of the camera{}: this "
        "machine processes the scan slower than the camera takes it; the cloud has no profiles "
        "there and the odometry tracks across each drop",
        frames_dropped_live, percent(frames_dropped_live, frames + frames_dropped_live),
        live_max_lag_s, others_dropped));
  }
  long main_points = points;  // the main camera's, placed: of frames with a pose
  for (const auto& camera : other_cameras) main_points -= camera.points;
  const int placed_frames = frames_with_line - frames_without_pose;
  if (placed_frames > 0 && scan_lines > 0 &&
      static_cast<double>(main_points) / placed_frames < 0.5 * scan_lines) {
    warnings.push_back("the profiles are short: " + std::to_string(main_points / placed_frames) +
                       " points per frame of " + std::to_string(scan_lines) +
                       " scan lines (the line fades into the water or leaves the scene)");
  }
  const auto count = [&](const char* key) {
    return pose_details.is_object() && pose_details.contains(key) &&
                   pose_details[key].is_number_integer()
               ? pose_details[key].get<int>()
               : 0;
  };
  const auto without_pose = [&](int n, const std::string& when, const std::string& why) {
    warnings.push_back(std::to_string(n) + " frame(s) (" + percent(n, frames) + " %) got no pose" +
                       when + " and are left out of the cloud (" + why + ")");
  };
  // --poses far sparser than the frames (or in milliseconds: a log's
  // 7 ms steps read as 7 s): each profile's pose is interpolated over far
  // more motion than the trajectory measured.
  if (external_pose_step_s > 1.0 ||
      (external_poses_in_scan >= 0 && external_poses_in_scan < 2 && sequence_duration_s > 0.0)) {
    warnings.push_back(fmt::format(
        "{}'s poses are {:.3g} s apart (median), and the frames' {:.3g} s hold {} of them: every "
        "profile is placed with a pose interpolated over that, whatever the platform did "
        "between{}",
        pose_source, external_pose_step_s, sequence_duration_s, external_poses_in_scan,
        external_pose_step_s > 1.0 ? " (are its times in milliseconds? divide them by 1000)" : ""));
  }
  const bool tracked = pose_source.rfind("self-referenced", 0) == 0;
  if (frames_without_pose > 0 && !tracked) {
    // An external trajectory has none outside its times (--poses).
    without_pose(frames_without_pose, "",
                 pose_source.empty() ? "the poses have none at their times"
                                     : pose_source + " has none at their times");
  } else if (frames_without_pose > 0) {
    // Held while the odometry waited to start (or to start again), or lost.
    const int waiting = std::min(count("frames_without_pose_at_start"), frames_without_pose);
    if (waiting > 0) {
      std::string why =
          "it starts once the laser's profiles span the scene's plane across the line and "
          "enough features are tracked";
      if (const int refused = count("start_attempts_refused"); refused > 0) {
        why += "; " + std::to_string(refused) +
               " start attempt(s) found the held frames' profiles too narrow once tracked, or "
               "their plane running through the camera: the laser sweeps slowly, or the "
               "platform moved with the sweep";
        if (const int unsettled = count("start_attempts_refused_unsettled"); unsettled > 0) {
          why += " (" + std::to_string(unsettled) +
                 " of them because the held frames' poses began to diverge before they settled)";
        }
      }
      without_pose(waiting, " while the odometry waited to start", why);
    }
    if (frames_without_pose > waiting)
      without_pose(frames_without_pose - waiting, "", "tracking lost");
  }
  for (const auto& camera : other_cameras) {
    if (camera.frames_without_pose > 0 || camera.frames_with_line < 0.9 * camera.frames) {
      warnings.push_back(
          "camera " + camera.name + ": " + std::to_string(camera.frames - camera.frames_with_line) +
          " frame(s) without a laser line, " + std::to_string(camera.frames_without_pose) +
          " outside the main camera's trajectory (left out)");
    }
  }
  if (count("lost") > 0) {
    warnings.push_back("visual tracking was lost " + std::to_string(count("lost")) +
                       " time(s) and restarted (too few features: turbid water, no texture, "
                       "fast motion)");
  }
  // A hover keeps its keyframe for many frames; a new one every few frames
  // means the features do not last (low contrast), and the poses suffer.
  if (count("tracked") >= 20 && count("keyframes") > 0.3 * count("tracked")) {
    warnings.push_back("features are short-lived: a new keyframe in " +
                       percent(count("keyframes"), count("tracked")) +
                       " % of the tracked frames (low contrast: turbid water or a dark, bare "
                       "scene); expect a less accurate trajectory");
  }
  if (frames_with_static_detections > 0) {
    warnings.push_back("in " + std::to_string(frames_with_static_detections) +
                       " frame(s) line candidates on 5 % or more of the scan lines behaved like "
                       "scene texture (stayed put while the laser swept, or moved with the scene "
                       "under a fixed laser: a stripe or a reflection in the scene that could "
                       "be taken for the line, or a surface the sheet grazes): ignored, " +
                       std::to_string(static_detections_removed) +
                       " in all (--keep-static-detections keeps them)");
  }
  if (frames_clipping_examined > 0 &&
      frames_with_clipped_scene >= laser::kClippedFramesToWarn * frames_clipping_examined) {
    warnings.push_back(laser::ClippedSceneWarning(frames_with_clipped_scene, ClippedSceneShare()));
  }
  if (frames_features_clipping_examined > 0 &&
      frames_with_clipped_features >=
          laser::kClippedFramesToWarn * frames_features_clipping_examined) {
    warnings.push_back(laser::ClippedFeaturesWarning(frames_with_clipped_features,
                                                     ClippedFeaturesShare(), features_colour));
  }
  if (frames_with_off_colour > 0) {
    std::string warning =
        "in " + std::to_string(frames_with_off_colour) + " frame(s) bright spots beside the line " +
        "showed too little of the laser's colour signature (lit by the floods, not the laser: " +
        "marine snow or other particles near the lights): ignored, " +
        std::to_string(off_colour_points) + " candidates in all (--keep-off-colour keeps them)";
    // Particles in many frames are features too, at the wrong depth
    // (BENCHMARKS.md, "The laser's colour signature against marine snow").
    if (pose_source.rfind("self-referenced", 0) == 0 &&
        frames_with_off_colour >= 0.05 * frames_lit) {
      warning +=
          "; the odometry's features on such particles take the depth of the scene behind "
          "them, so expect the trajectory's scale to be off (15-26 % at one particle per litre "
          "in the simulator; an INS trajectory with --poses places the cloud better)";
    }
    warnings.push_back(warning);
  }
  // A few such points are things lit far from the line; many mean the
  // line is seen far off, or the camera and laser stand too close together.
  if (grazing_points > 0 && grazing_points >= 0.01 * (points + grazing_points)) {
    warnings.push_back(fmt::format(
        "{} line point(s) dropped because their camera ray grazes the light sheet: a pixel of "
        "detection error would move them by more than {:g} % of their range (the line seen far "
        "off, or the camera and laser too close together for the range; "
        "--max-range-error-per-px)",
        grazing_points, 100.0 * max_range_error_per_px));
  }
  if (count("bundle_adjustments_stopped_by_time_limit") > 0) {
    warnings.push_back(std::to_string(count("bundle_adjustments_stopped_by_time_limit")) + " of " +
                       std::to_string(count("bundle_adjustments")) +
                       " windowed bundle adjustments stopped at their time limit before "
                       "converging: the trajectory depends on the machine's load "
                       "(--ba-time-limit)");
  }
  if (passes_settled == false && !pass_changes.empty()) {
    // A surface in front of the main one (a shaft before a hull): each pass
    // places it with the poses of the one before.
    warnings.push_back(fmt::format(
        "the trajectory had not settled after {} passes: the last moved it by {:.1f} mm and "
        "{:.2f} deg rms (settled: below {:g} mm and {:g} deg); the depths of the surface in "
        "front of the scene's main one, and so the poses, may still be off (--passes)",
        passes, 1e3 * pass_changes.back().moved_m, pass_changes.back().turned_deg,
        1e3 * passes_settled_within.moved_m, passes_settled_within.turned_deg));
  }
  if (!later_pass_failed.empty()) {
    warnings.push_back(fmt::format(
        "pass {} failed ({}): these outputs are pass {}'s, and the depths of the surface in front "
        "of the scene's main one, and so the poses, may still be off (run again for the passes "
        "that settle them)",
        passes + 1, later_pass_failed, passes));
  }
  if (surface_in_front && passes == 1 && later_pass_failed.empty()) {
    // One pass on a hull with a shaft in front: the shaft's features had
    // the hull's depth until the laser reached the shaft (BENCHMARKS.md,
    // "A live run in front of a hull").
    warnings.push_back(
        "the scene has a surface standing in front of its main one (a shaft before a hull): "
        "in one pass (--live, --passes 1) the odometry gave that surface's features the main "
        "one's depth until the laser reached it, so the trajectory and the surface in front may "
        "be off by centimetres; offline, uwscan reconstruct without --live runs the odometry "
        "again on the surface measured over the whole scan (--passes auto)");
  }
  if (const std::optional<UnsettledStart> start = FindUnsettledStart(pose_details)) {
    // A smaller tracked image averages more of the sensor's noise in each
    // KLT window: on the simulator's 640x480 hovers in water of c_p
    // 0.5-0.8 every start still moving by 4-20 mm at 640 px settled at 320
    // px, with the trajectory's error 1.5-2.9x lower, and far from settled
    // at c_p 0.7-1.0 five of six came back from 0.05-0.56 of their true
    // scale to 0.85-1.07 (RunReconstruct does so by itself unless
    // --max-tracking-width was given; BENCHMARKS.md, "Turbid water,
    // measured again", "Turbid hovers: a start still moving runs again on
    // half the image").
    const std::optional<int> half = SmallerTrackingWidth();
    const std::string smaller =
        half ? fmt::format(
                   "; a smaller tracked image averages more of the sensor's noise: try "
                   "--max-tracking-width {}",
                   *half)
             : "";
    // Far from settled, the held frames' tracks do not hold the scene still
    // (faint, noisy features), and every later pose rests on that start: in
    // turbid water the simulator's hovers came out at 0.05-0.56 of their
    // true scale above 10x the tolerance. Below it they may still be far
    // off (BENCHMARKS.md, "Turbid water, measured again").
    if (start->Far()) {
      warnings.push_back(fmt::format(
          "the frames held at the start had not settled after {} refinements: their poses "
          "still moved {:.1f} mm rms, more than ten times the {:g} mm they settle within: the "
          "features did not hold the scene still (too faint or noisy: turbid water, a dark "
          "scene; or the platform moved far while the frames were held); the whole trajectory "
          "rests on that start, its scale may be off by tens of percent and cloud.ply may be "
          "no better than cloud_uncompensated.ply (an INS trajectory with --poses places the "
          "cloud better){}",
          count("start_refinements"), *start->moved_mm, start->within_mm, smaller));
    } else if (!start->moved_mm) {
      warnings.push_back(fmt::format(
          "the frames held at the start had not settled after {} refinements: the odometry "
          "lost the held frames each time it tracked them again, so no two refinements could "
          "be compared: the start of the trajectory may be off, and with it the rest (too few "
          "features to track: a platform moving fast for the frame rate, turbid water, a dark "
          "scene)",
          count("start_refinements")));
    } else {
      const std::string turned = start->turned_deg && *start->turned_deg >= start->within_deg
                                     ? fmt::format(" and turned {:.2f} deg", *start->turned_deg)
                                     : "";
      warnings.push_back(fmt::format(
          "the frames held at the start had not settled after {} refinements (their poses still "
          "moved {:.1f} mm{} rms): the start of the trajectory may be off, and with it the rest "
          "(a sweep too fast or too short for the scene's plane, or features too faint or noisy "
          "to track: turbid water, a dark scene; --max-init-refinements){}",
          count("start_refinements"), *start->moved_mm, turned, smaller));
    }
  }
  if (!tracking_retry_failed.empty()) {
    warnings.push_back("run again on half the tracked image, the odometry failed (" +
                       tracking_retry_failed + "): these outputs are the first run's");
  }
  if (tracking_retried_from_width > 0) {
    warnings.push_back(fmt::format(
        "the start had not settled tracking the image at {} px (its poses still moved {:.1f} mm "
        "rms): the odometry ran again at {} px, which averages more of the sensor's noise, and "
        "these outputs are that run's (--max-tracking-width {} keeps the first)",
        tracking_retried_from_width, retried_start_change_mm, tracking_retried_from_width / 2,
        tracking_retried_from_width));
  }
  if (count("implausible_poses_rejected") > 0) {
    warnings.push_back(std::to_string(count("implausible_poses_rejected")) +
                       " pose(s) moved faster than a vehicle can and were rejected");
  }
  return warnings;
}

nlohmann::json CameraReport::ToJson() const {
  return {{"camera", name},
          {"laser", laser},
          {"frames", frames},
          {"frames_with_line", frames_with_line},
          {"frames_without_pose", frames_without_pose},
          {"frames_dropped_live", frames_dropped_live},
          {"points", points}};
}

std::optional<LiveLag> SummarizeLiveLag(std::vector<std::pair<double, double>> lags,
                                        double sequence_duration_s) {
  if (lags.empty()) return std::nullopt;
  // In delivery order (a further camera's frames join between the main
  // camera's, and may come a little after later frames of it).
  std::stable_sort(lags.begin(), lags.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  LiveLag live;
  std::vector<double> values;
  for (const auto& [delivered_s, lag_s] : lags) {
    values.push_back(lag_s);
    if (values.size() == 1 || lag_s > live.max_s) {
      live.max_s = lag_s;
      live.max_at_scan_s = delivered_s;
    }
  }
  live.last_s = lags.back().second;
  live.median_s = Median(std::move(values));
  size_t next = 0;  // the first frame delivered after the second before
  std::optional<double> latest;
  for (int second = 1; second <= static_cast<int>(sequence_duration_s); ++second) {
    while (next < lags.size() && lags[next].first <= second) latest = lags[next++].second;
    live.at_each_second_s.push_back(latest);
  }
  return live;
}

nlohmann::json LiveLag::ToJson() const {
  nlohmann::json seconds = nlohmann::json::array();
  for (const auto& lag : at_each_second_s) seconds.push_back(lag ? nlohmann::json(*lag) : nullptr);
  return {{"max", max_s},
          {"max_at_scan_s", max_at_scan_s},
          {"median", median_s},
          {"last", last_s},
          {"at_each_second", seconds}};
}

nlohmann::json ReconstructReport::ToJson() const {
  nlohmann::json cameras = nlohmann::json::array();
  for (const auto& camera : other_cameras) cameras.push_back(camera.ToJson());
  std::vector<double> pass_moves_mm, pass_turns_deg;
  for (const fusion::PoseChange& change : pass_changes) {
    pass_moves_mm.push_back(1e3 * change.moved_m);
    pass_turns_deg.push_back(change.turned_deg);
  }
  // What the first frame showed, null if nothing.
  const auto or_null = [](bool found, const auto& value) {
    return found ? nlohmann::json(value) : nlohmann::json();
  };
  return {
      {"frames", frames},
      {"warnings", Warnings()},
      {"frames_with_line", frames_with_line},
      {"frames_laser_off", frames_laser_off},
      {"lines_detected_on_difference_images", frames_on_difference},
      {"frames_without_pose", frames_without_pose},
      {"points", points},
      {"points_uncompensated", points_uncompensated},
      {"triangulation_failures", triangulation_failures},
      {"static_candidates_ignored", static_detections_removed},
      {"texture_candidates_matched_epipolar", texture_epipolar_matches},
      {"line_ranges", line_ranges},
      {"laser_sweeps", laser_sweeps},
      {"contrast_scale", contrast_scale},
      {"log_offset", log_offset},
      {"points_dropped_on_albedo_edges", albedo_edge_points},
      {"off_colour_candidates_ignored", off_colour_points},
      {"frames_with_off_colour_candidates", frames_with_off_colour},
      {"grazing_points_dropped", grazing_points},
      {"laser_pose_inverse_fits", laser_pose_inverse_fits},
      {"laser_seen_in", or_null(!laser_seen_in.empty(), laser_seen_in)},
      {"laser_on_inverted_at", or_null(laser_on_inverted_at >= 0, laser_on_inverted_at)},
      {"max_range_error_per_px", max_range_error_per_px},
      {"frames_sweep_filter_restored", frames_sweep_filter_restored},
      {"frames_with_clipped_scene", frames_with_clipped_scene},
      {"clipped_scene_share", ClippedSceneShare()},
      {"frames_with_clipped_features", frames_with_clipped_features},
      {"clipped_features_share", ClippedFeaturesShare()},
      {"features_colour", features_colour},
      {"sample_bits", sample_bits},
      {"low_sample_bits", or_null(first_frame.low_sample_bits > 0, first_frame.low_sample_bits)},
      {"mosaic_phase_ratio",
       or_null(first_frame.mosaic_phase_ratio > 0, first_frame.mosaic_phase_ratio)},
      {"bayer_doubt", or_null(!first_frame.other_bayer.empty(), first_frame.other_bayer)},
      {"first_frame_lit_share", first_frame.lit_share},
      {"pose_source", pose_source},
      {"external_pose_step_s", or_null(external_pose_step_s >= 0.0, external_pose_step_s)},
      {"external_poses_in_scan", or_null(external_poses_in_scan >= 0, external_poses_in_scan)},
      {"pose", pose_details},
      {"other_cameras", cameras},
      {"timing_s",
       {{"total", seconds},
        {"laser_detection", seconds_detect},
        {"triangulation", seconds_triangulate},
        {"pose_estimation", seconds_pose},
        {"io", seconds_io},
        {"waiting_for_images", seconds_waiting_for_images},
        {"earlier_passes", seconds_earlier_passes}}},
      {"passes", passes},
      {"pass_changes_mm", pass_moves_mm},
      {"pass_changes_deg", pass_turns_deg},
      {"passes_settled", passes_settled ? nlohmann::json(*passes_settled) : nlohmann::json()},
      {"surface_in_front", surface_in_front},
      {"tracking_retried_from_width", tracking_retried_from_width},
      {"retried_start_last_change_mm", retried_start_change_mm},
      {"tracking_retry_failed", tracking_retry_failed},
      {"later_pass_failed", later_pass_failed},
      {"track_every", track_every},
      {"start_screen_every", start_screen_every},
      {"smoothing_half_window", smoothing_half_window},
      {"line_window_px", line_window_px},
      {"frames_line_window_redone", frames_line_window_redone},
      {"async_bundle_adjustment", async_bundle_adjustment},
      {"live_lag_s", live_lag ? live_lag->ToJson() : nlohmann::json()},
      {"live_max_lag_s", live_max_lag_s > 0 ? nlohmann::json(live_max_lag_s) : nlohmann::json()},
      {"frames_dropped_live", frames_dropped_live},
      {"sequence_duration_s", sequence_duration_s},
      {"frames_missing", frame_gaps.missing},
      {"frame_gaps", frame_gaps.gaps},
      {"frame_step_s", frame_gaps.median_step_s},
      {"longest_frame_gap_s", frame_gaps.longest_s},
      {"real_time_factor", RealTimeFactor()}};
}

}  // namespace uwscan
