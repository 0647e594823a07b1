// uwscan laser detect
#include <cmath>
#include <cstdio>
#include <string>

#include "commands.h"
#include "uwscan/io/image.h"
#include "uwscan/laser/clipping.h"
#include "uwscan/laser/profile.h"
#include "uwscan/pipeline/laser_detect.h"
#include "uwscan/util/error.h"

namespace uwscan::cli {

void RegisterLaserCommands(CLI::App& app) {
  auto* laser = app.add_subcommand("laser", "Laser line detection and profiles");
  laser->require_subcommand(1);
  auto job = std::make_shared<LaserDetectJob>();
  auto images = std::make_shared<std::string>();
  auto rig = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  auto profiles = std::make_shared<std::string>();
  auto overlay = std::make_shared<std::string>();
  auto method = std::make_shared<std::string>("thesis");
  auto* detect = laser->add_subcommand(
      "detect", "Detect the laser line in every image: frame,u,v,channel,strength");
  auto dataset = std::make_shared<std::string>();
  auto* dataset_option =
      detect->add_option("--dataset", *dataset, "dataset folder (rig.yaml, frames.csv, frames/)");
  auto* images_option =
      detect->add_option("--images", *images, "folder of images (sorted by name)");
  dataset_option->excludes(images_option);

  detect->add_option("--rig", *rig, "rig.yaml: image size, Bayer pattern, laser colour and pose");
  detect->add_option("--camera", job->camera_name, "camera name (default: the first)");
  AddSampleBitsOption(detect, &job->sample_bits);
  detect->add_option("--out", *out, "detections.csv")->required();
  detect->add_option("--method", *method, "thesis | cog | argmax")->capture_default_str();
  detect->add_option("--overlay", *overlay, "folder for images with the detections drawn");
  detect->add_option(
      "--profiles", *profiles,
      "profiles.csv: triangulated points frame,x,y,z (camera frame, m), without those whose "
      "camera ray grazes the light sheet (as reconstruct)");
  detect->add_option("--scan", job->scan, "rows | cols | auto")->capture_default_str();
  detect->add_option("--channel", job->channel, "red | green | blue | auto")->capture_default_str();
  detect
      ->add_option("--albedo", job->albedo,
                   "channel whose albedo corrects the sub-pixel fit: red | green | blue | none "
                   "| auto (red for a green laser)")
      ->capture_default_str();
  detect->add_option("--sigma", job->detector.line_sigma_px, "expected line sigma (px)")
      ->capture_default_str();
  auto keep_off_colour = std::make_shared<bool>(false);
  detect->add_flag(
      "--keep-off-colour", *keep_off_colour,
      "keep line candidates whose third colour shows less than " +
          std::to_string(std::lround(100 * laser::DetectorOptions{}.min_signature_share)) +
          " % of the laser's share of light (as reconstruct --keep-off-colour)");
  detect->add_flag("--quiet", job->quiet, "no progress and no summary");
  detect->callback([=] {
    const auto parsed = laser::MethodFromName(*method);
    if (!parsed) throw UsageError("--method must be thesis, cog or argmax");
    job->detector.method = *parsed;
    if (*keep_off_colour) job->detector.min_signature_share = 0.0;
    if (dataset->empty() == images->empty()) throw UsageError("give either --dataset or --images");
    job->dataset_dir = *dataset;
    job->images_dir = *images;
    job->detections_csv = *out;
    if (!rig->empty()) job->rig_path = *rig;
    if (!profiles->empty()) job->profiles_csv = *profiles;
    if (!overlay->empty()) job->overlay_dir = *overlay;
    const LaserDetectSummary s = RunLaserDetect(*job);
    for (const std::string& warning : s.first_frame.Warnings())
      std::fprintf(stderr, "laser detect: warning: %s\n", warning.c_str());
    if (!s.laser_colour_warning.empty())
      std::fprintf(stderr, "laser detect: warning: %s\n", s.laser_colour_warning.c_str());
    const std::string missed = laser::MissedSheetWarning(
        s.missed_points, s.profile_points + s.grazing_points, s.laser_pose_inverse_fits);
    if (!missed.empty()) std::fprintf(stderr, "laser detect: warning: %s\n", missed.c_str());
    if (!job->quiet) {
      const std::string laser_off =
          s.frames_laser_off > 0
              ? ", " + std::to_string(s.frames_laser_off) + " with the laser off (skipped)"
              : "";
      std::fprintf(stderr,
                   "laser detect: %d frames (%d without a line%s, %d unreadable), %ld points, "
                   "%.1f frames/s -> %s\n",
                   s.frames, s.frames_without_line, laser_off.c_str(), s.unreadable_frames,
                   s.points, s.frames / std::max(s.seconds, 1e-9), out->c_str());
      if (s.frames > 0 && s.frames_with_clipped_scene >= laser::kClippedFramesToWarn * s.frames) {
        std::fprintf(
            stderr, "laser detect: warning: %s\n",
            laser::ClippedSceneWarning(s.frames_with_clipped_scene, s.clipped_scene_share).c_str());
      }
      if (s.grazing_points > 0) {
        std::fprintf(stderr,
                     "laser detect: %ld point(s) left out of the profiles: their camera ray "
                     "grazes the light sheet (a pixel of error would move them by more than "
                     "%g %% of their range)\n",
                     s.grazing_points, 100.0 * laser::kMaxRangeErrorPerPixel);
      }
    }
  });
}

}  // namespace uwscan::cli
