// uwscan vo --dataset DIR --out trajectory.tum [--model pinhole|flatport] [--mask-laser]
// uwscan vo synth --out DIR [--scenario transect|hover] ...   (synthetic datasets)
#include <cstdio>

#include "commands.h"
#include "uwscan/pipeline/vo_benchmark.h"
#include "uwscan/pipeline/vo_run.h"
#include "uwscan/pipeline/vo_synthetic.h"
#include "uwscan/util/error.h"

namespace uwscan::cli {

void RegisterVoCommand(CLI::App& app) {
  auto* vo = app.add_subcommand(
      "vo", "Monocular visual odometry (flat-port or pinhole model): trajectory.tum");
  vo->require_subcommand(0, 1);
  auto job = std::make_shared<VoJob>();
  auto dataset = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  auto status = std::make_shared<std::string>();
  auto projection = std::make_shared<std::string>("exact");
  vo->add_option("--dataset", *dataset, "dataset folder (rig.yaml, frames.csv, frames/)");
  vo->add_option("--out", *out, "trajectory.tum (world_from_camera; gaps as '# gap' comments)");
  vo->add_option("--status", *status, "per-frame status CSV (tracked/lost/reinitialized/...)");
  vo->add_option("--camera", job->camera_name, "camera name (default: the first)");
  vo->add_option("--model", job->model, "flatport | pinhole")->capture_default_str();
  vo->add_option("--projection", *projection,
                 "flat-port residual in the bundle adjustment: exact | taylor")
      ->capture_default_str();
  vo->add_option("--pinhole-fit-depth", job->pinhole_fit_depth_m,
                 "--model pinhole: depth (m) of the plane the pinhole is fitted on")
      ->capture_default_str();
  vo->add_flag("--mask-laser", job->mask_laser, "detect the laser line and ignore its pixels");
  vo->add_option("--mask-margin", job->mask_margin_px,
                 "--mask-laser: pixels ignored on each side of the detected line")
      ->capture_default_str();
  vo->add_option("--initial-depth", job->odometry.initial_median_depth_m,
                 "expected median scene distance at the start (m): the scale prior")
      ->capture_default_str();
  vo->add_option("--window", job->odometry.ba.window_size, "keyframes in the windowed BA")
      ->capture_default_str();
  vo->add_option("--ba-history", job->odometry.ba.history_keyframes,
                 "keyframes before the window whose rays of its points enter the BA, held")
      ->capture_default_str();
  vo->add_option("--klt-window", job->odometry.tracker.klt_window_px, "KLT window (px, odd)")
      ->capture_default_str();
  vo->add_option("--per-cell", job->odometry.tracker.max_per_cell,
                 "features per grid cell (8x6 grid)")
      ->capture_default_str();
  vo->add_option("--max-dormant-frames", job->odometry.tracker.max_dormant_frames,
                 "frames a track cut by the laser line (or lost by KLT) may stay lost and still be "
                 "taken up again under its id (0 = off)")
      ->capture_default_str();
  vo->add_option("--max-tracking-width", job->max_tracking_width,
                 "frames wider than this are tracked halved until at most this wide, but not "
                 "below 160 px (raw Bayer: the LED colour's own samples, no demosaicking); 0 = "
                 "full resolution")
      ->capture_default_str();
  vo->add_option("--contrast-scale", job->contrast_sigma_fraction,
                 "equalise the tracked image's contrast over a Gaussian of this fraction of its "
                 "width (the lights travel with the camera; 0 = off)")
      ->capture_default_str();
  vo->add_option("--ba-time-limit", job->odometry.ba.max_solver_time_s,
                 "seconds one windowed BA may take before it stops unconverged")
      ->capture_default_str();
  vo->add_option("--ba-iterations", job->odometry.ba.max_iterations,
                 "iterations one windowed BA may take")
      ->capture_default_str();
  AddAsyncBundleAdjustmentFlags(vo, &job->async_bundle_adjustment,
                                "windowed BA on a second thread, its result joining the map 8 "
                                "frames later (frames are not held up by it); by default above "
                                "100 Hz");
  vo->add_option("--max-frames", job->max_frames, "stop after this many frames (0 = all)");
  AddSampleBitsOption(vo, &job->sample_bits);
  vo->add_flag("--quiet", job->quiet, "no progress and no summary");

  auto synth_options = std::make_shared<SyntheticVoOptions>();
  auto synth_out = std::make_shared<std::string>();
  auto* synth = vo->add_subcommand(
      "synth", "Write a synthetic VO dataset (textured sea floor, ground truth)");
  synth->add_option("--out", *synth_out, "dataset folder to create")->required();
  synth->add_option("--scenario", synth_options->scenario, "transect | hover")
      ->capture_default_str();
  synth->add_option("--frames", synth_options->frames, "number of frames")->capture_default_str();
  synth->add_option("--width", synth_options->width, "image width (height = 3/4)")
      ->capture_default_str();
  synth->add_option("--length", synth_options->length_m, "transect length (m)")
      ->capture_default_str();
  synth->add_option("--altitude", synth_options->altitude_m, "altitude (m)")->capture_default_str();
  synth->add_option("--d-air", synth_options->d_air_m, "camera centre to port (m)")
      ->capture_default_str();
  synth->add_option("--medium", synth_options->medium, "clear | medium")->capture_default_str();
  synth->add_option("--rate", synth_options->frame_rate_hz, "frame rate (Hz)")
      ->capture_default_str();
  synth->add_option("--seed", synth_options->seed, "texture and noise seed")->capture_default_str();
  auto no_laser = std::make_shared<bool>(false);
  synth->add_flag("--no-laser", *no_laser, "no laser line");
  synth->callback([=] {
    synth_options->laser = !*no_laser;
    const SyntheticVoSummary s = WriteSyntheticVoDataset(*synth_out, *synth_options);
    std::fprintf(stderr, "vo synth: %d frames, path %.2f m, %.1f s -> %s\n", s.frames,
                 s.path_length_m, s.seconds, synth_out->c_str());
  });

  auto bench_options = std::make_shared<VoBenchmarkOptions>();
  auto* bench = vo->add_subcommand(
      "bench", "Speed and memory on frames rendered in memory (circling over a sea floor)");
  bench->add_option("--frames", bench_options->frames, "frames")->capture_default_str();
  bench->add_option("--width", bench_options->width, "image width (height = 3/4)")
      ->capture_default_str();
  bench->add_option("--d-air", bench_options->d_air_m, "camera centre to port (m)")
      ->capture_default_str();
  bench->add_option("--step", bench_options->speed_m_per_frame, "motion per frame (m)")
      ->capture_default_str();
  bench->add_option("--memory-every", bench_options->memory_every, "RSS sample interval (frames)")
      ->capture_default_str();
  bench->add_option("--klt-window", bench_options->klt_window_px, "KLT window (px, odd)")
      ->capture_default_str();
  bench->add_flag("--async-ba", bench_options->async_bundle_adjustment,
                  "windowed BA on a second thread");
  bench->add_flag("--quiet", bench_options->quiet, "no progress");
  bench->callback([=] {
    const VoBenchmarkResult r = RunVoBenchmark(*bench_options);
    const int height = bench_options->width * 3 / 4;
    std::printf("vo bench %dx%d, %d frames: %d tracked, %d lost, %d reinitialised, %d keyframes\n",
                bench_options->width, height, r.frames, r.tracked, r.lost, r.reinitialised,
                r.keyframes);
    std::printf("CPU time: tracking alone %.1f frames/s, full VO %.1f frames/s (%.2f ms/frame)\n",
                r.frames / std::max(r.tracking_cpu_s, 1e-9), r.frames / std::max(r.vo_cpu_s, 1e-9),
                1e3 * r.vo_cpu_s / r.frames);
    std::printf(
        "wall clock: tracking alone %.1f frames/s, full VO %.1f frames/s (slowest frame "
        "%.1f ms); rendering not counted (%.1f s)\n",
        r.frames / std::max(r.tracking_s, 1e-9), r.frames / std::max(r.vo_s, 1e-9),
        1e3 * r.max_frame_s, r.render_s);
    std::printf("map: at most %d points, %d keyframes\nRSS (kB) by frame:", r.max_map_points,
                r.max_keyframes);
    for (const auto& [frame, kb] : r.rss_kb) std::printf(" %d:%ld", frame, kb);
    std::printf("\n");
  });

  vo->callback([=] {
    if (synth->parsed() || bench->parsed()) return;
    if (dataset->empty() || out->empty()) throw UsageError("vo needs --dataset and --out");
    if (*projection == "exact") {
      job->odometry.ba.method = ProjectionMethod::kExact;
    } else if (*projection == "taylor") {
      job->odometry.ba.method = ProjectionMethod::kTaylor;
    } else {
      throw UsageError("--projection must be exact or taylor");
    }
    job->dataset_dir = *dataset;
    job->trajectory_out = *out;
    if (!status->empty()) job->status_out = *status;
    const VoRunSummary s = RunVisualOdometry(*job);
    for (const std::string& warning : s.warnings) {
      std::fprintf(stderr, "uwscan: warning: %s\n", warning.c_str());
    }
    if (job->quiet) return;
    std::fprintf(stderr,
                 "vo: %d frames: %d posed, %d tracked, %d lost, %d reinitialised, %d invalid, "
                 "%d unreadable; %d keyframes, %d gaps -> %s\n",
                 s.frames, s.posed, s.tracked, s.lost, s.reinitialised, s.invalid, s.unreadable,
                 s.keyframes, s.gaps, out->c_str());
    std::fprintf(stderr, "tracked: %s\n", s.tracked_image.c_str());
    if (job->mask_laser) {
      std::fprintf(stderr, "tracks: %ld lost on the laser mask, %ld taken up again after a loss\n",
                   s.tracks_lost_on_mask, s.tracks_reacquired);
    }
    std::fprintf(stderr,
                 "speed (CPU time): VO %.1f frames/s, tracking alone %.1f frames/s; wall clock: VO "
                 "%.1f frames/s; windowed BA %.1f ms/frame (wall); laser mask %.1f ms/frame; total "
                 "%.1f s incl. image reading\n",
                 s.frames / std::max(s.vo_cpu_s, 1e-9), s.frames / std::max(s.tracking_cpu_s, 1e-9),
                 s.frames / std::max(s.vo_s, 1e-9),
                 1e3 * s.bundle_adjustment_s / std::max(s.frames, 1),
                 1e3 * s.mask_s / std::max(s.frames, 1), s.wall_s);
    std::fprintf(stderr, "windowed BA%s: %d solves, %d stopped by the %.2f s time limit%s\n",
                 s.async_bundle_adjustment ? " (own thread)" : "", s.bundle_adjustments,
                 s.bundle_adjustments_time_limited, job->odometry.ba.max_solver_time_s,
                 s.bundle_adjustments_time_limited > 0
                     ? " (their results depend on the machine's load; --ba-time-limit)"
                     : "");
    std::fprintf(stderr, "memory: RSS %ld kB at 10 %% of the run, %ld kB at the end, peak %ld kB\n",
                 s.rss_kb_at_10_percent, s.rss_kb_end, s.peak_rss_kb);
    if (s.metrics) std::fprintf(stderr, "%s", FormatTrajectoryMetrics(*s.metrics).c_str());
  });
}

}  // namespace uwscan::cli
