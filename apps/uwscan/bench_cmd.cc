// uwscan bench projection
#include <iostream>

#include "commands.h"
#include "uwscan/pipeline/laser_accuracy_benchmark.h"
#include "uwscan/pipeline/laser_benchmark.h"
#include "uwscan/pipeline/pipeline_benchmark.h"
#include "uwscan/pipeline/projection_benchmark.h"
#include "uwscan/pipeline/reconstruct.h"
#include "uwscan/pipeline/track_accuracy_benchmark.h"
#include "uwscan/util/error.h"

namespace uwscan::cli {

void RegisterBenchCommands(CLI::App& app) {
  auto* bench = app.add_subcommand("bench", "Speed benchmarks, printed as JSON");
  bench->require_subcommand(1);
  auto options = std::make_shared<ProjectionBenchmarkOptions>();
  auto* projection = bench->add_subcommand(
      "projection", "Projections/s of pinhole, Taylor (1-3 iterations) and exact on Flat1-3");
  projection->add_option("--points", options->points, "points per camera")->capture_default_str();
  projection->add_option("--repetitions", options->repetitions, "best of N")->capture_default_str();
  auto markdown = std::make_shared<bool>(false);
  projection->add_flag("--markdown", *markdown, "print Markdown tables instead of JSON");
  projection->callback([options, markdown] {
    const auto rates = RunProjectionBenchmark(*options);
    const auto accuracy = RunTaylorAccuracy();
    if (*markdown) {
      std::cout << ProjectionBenchmarkToMarkdown(rates, accuracy);
    } else {
      std::cout << ProjectionBenchmarkToJson(rates, accuracy, *options).dump(2) << "\n";
    }
  });

  auto laser_options = std::make_shared<LaserBenchmarkOptions>();
  auto* laser = bench->add_subcommand(
      "laser", "Frames/s of the thesis laser detector and the argmax and cog baselines");
  laser->add_option("--width", laser_options->width, "synthetic frames' width (px)")
      ->capture_default_str();
  laser->add_option("--height", laser_options->height, "synthetic frames' height (px)")
      ->capture_default_str();
  laser->add_option("--frames", laser_options->frames, "distinct frames")->capture_default_str();
  laser->add_option("--repetitions", laser_options->repetitions, "best of N passes")
      ->capture_default_str();
  laser->add_flag("--bayer", laser_options->bayer, "raw RGGB frames instead of 8-bit mono");
  auto dataset = std::make_shared<std::string>();
  laser->add_option("--dataset", *dataset,
                    "use this dataset's frames and rig (e.g. from uwscan simulate tank-target)");
  laser->callback([laser_options, dataset] {
    std::vector<cv::Mat> frames;
    laser::ColourLayout layout =
        laser_options->bayer ? laser::ColourLayout::kBayerRggb : laser::ColourLayout::kMono;
    std::string source = laser_options->bayer ? "synthetic-rggb" : "synthetic-mono";
    laser::DetectorOptions detector;
    if (dataset->empty()) {
      frames = MakeLaserBenchmarkFrames(*laser_options);
    } else {
      frames = LoadDatasetFrames(*dataset, laser_options->frames, &layout, &detector);
      source = *dataset;
    }
    const auto rates = RunLaserBenchmark(frames, layout, *laser_options, detector);
    std::cout << LaserBenchmarkToJson(rates, frames.front().size(), static_cast<int>(frames.size()),
                                      source)
                     .dump(2)
              << "\n";
  });

  auto accuracy = std::make_shared<LaserAccuracyBenchmarkOptions>();
  auto* laser_accuracy = bench->add_subcommand(
      "laser-accuracy",
      "Laser detection RMS, completeness and outliers on simulated tank-target frames (Markdown)");
  laser_accuracy->add_option("--width", accuracy->width, "simulated frames' width (px)")
      ->capture_default_str();
  laser_accuracy->add_option("--height", accuracy->height, "simulated frames' height (px)")
      ->capture_default_str();
  laser_accuracy
      ->add_option("--frames", accuracy->frames,
                   "frames per water (servo positions over the sweep)")
      ->capture_default_str();
  laser_accuracy->add_option("--seed", accuracy->seed, "the simulation's random seed")
      ->capture_default_str();
  laser_accuracy->add_option("--turbidity", accuracy->turbidities, "presets or c_p(530) values");
  laser_accuracy->callback(
      [accuracy] { std::cout << LaserAccuracyToMarkdown(RunLaserAccuracyBenchmark(*accuracy)); });

  auto pipeline_options = std::make_shared<PipelineBenchmarkOptions>();
  auto pipeline_dataset = std::make_shared<std::string>();
  auto* pipeline = bench->add_subcommand(
      "pipeline",
      "Time the self-referenced reconstruction (real-time factor, peak memory, CPU time and "
      "cores kept busy, the load average before) as JSON");
  pipeline->add_option("--dataset", *pipeline_dataset, "dataset (default: simulate tank-target)");
  pipeline
      ->add_option("--frames", pipeline_options->frames, "frames to simulate (without --dataset)")
      ->capture_default_str();
  pipeline
      ->add_option("--width", pipeline_options->width,
                   "simulated frames' width (px; without --dataset)")
      ->capture_default_str();
  pipeline
      ->add_option("--height", pipeline_options->height,
                   "simulated frames' height (px; without --dataset)")
      ->capture_default_str();
  AddAsyncBundleAdjustmentFlags(pipeline, &pipeline_options->async_bundle_adjustment,
                                "as reconstruct --async-ba");
  auto pipeline_track_every = std::make_shared<std::string>("auto");
  pipeline->add_option("--track-every", *pipeline_track_every, "as reconstruct --track-every")
      ->capture_default_str();
  auto pipeline_start_screen_every = std::make_shared<std::string>("auto");
  pipeline
      ->add_option("--start-screen-every", *pipeline_start_screen_every,
                   "as reconstruct --start-screen-every")
      ->capture_default_str();
  pipeline->add_option("--line-window", pipeline_options->line_window_px,
                       "as reconstruct --line-window");
  pipeline->add_flag("!--no-preread", pipeline_options->preread,
                     "time the images' reading from wherever they are (disk or page cache) "
                     "instead of reading them once before the timed run");
  pipeline->add_flag("--live", pipeline_options->live,
                     "deliver the frames at the camera's pace, as a live camera would, and "
                     "report how far the cloud falls behind it (live_lag_s); one pass");
  pipeline->add_option("--live-max-lag", pipeline_options->live_max_lag_s,
                       "as reconstruct --live-max-lag (with --live)");
  pipeline->callback(
      [pipeline_options, pipeline_dataset, pipeline_track_every, pipeline_start_screen_every] {
        pipeline_options->dataset = *pipeline_dataset;
        pipeline_options->track_every = ParseTrackEvery(*pipeline_track_every);
        pipeline_options->start_screen_every =
            ParseTrackEvery(*pipeline_start_screen_every, "--start-screen-every");
        std::cout << RunPipelineBenchmark(*pipeline_options).dump(2) << "\n";
      });

  auto tracks_options = std::make_shared<TrackAccuracyOptions>();
  auto tracks_dataset = std::make_shared<std::string>();
  auto* tracks = bench->add_subcommand(
      "tracks",
      "The self-referenced odometry's feature tracks on a simulated dataset against the "
      "simulator's truth: flow gain (do tracks lag the motion?) and errors, as JSON");
  tracks
      ->add_option("--dataset", *tracks_dataset, "simulated dataset (scene.yaml, groundtruth.tum)")
      ->required();
  tracks->add_option("--frames", tracks_options->frames, "frames (0 = all)")->capture_default_str();
  tracks
      ->add_option("--anchor-every", tracks_options->anchor_every,
                   "frames between the tracker's anchors (as a hover's keyframes: tracks "
                   "keep their first anchors)")
      ->capture_default_str();
  tracks
      ->add_option("--contrast-scale", tracks_options->contrast_scale,
                   "as reconstruct --contrast-scale (0 = off)")
      ->capture_default_str();
  tracks->callback([tracks_options, tracks_dataset] {
    tracks_options->dataset = *tracks_dataset;
    std::cout << RunTrackAccuracyBenchmark(*tracks_options).ToJson().dump(2) << "\n";
  });
}

}  // namespace uwscan::cli
