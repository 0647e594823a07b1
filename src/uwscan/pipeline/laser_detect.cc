#include "uwscan/pipeline/laser_detect.h"

#include <chrono>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "uwscan/io/dataset.h"
#include "uwscan/io/image.h"
#include "uwscan/io/rig_yaml.h"
#include "uwscan/laser/clipping.h"
#include "uwscan/laser/profile.h"
#include "uwscan/util/atomic_file.h"
#include "uwscan/util/error.h"
#include "uwscan/util/interrupt.h"
#include "uwscan/util/progress.h"
#include "uwscan/util/stopwatch.h"

namespace uwscan {
namespace fs = std::filesystem;

void LaserDetectJob::Check() const {
  CheckSampleBitsOption(sample_bits);
  using Options = laser::DetectorOptions;
  UWS_USAGE_CHECK(detector.line_sigma_px > Options::kMinLineSigmaPx &&
                      detector.line_sigma_px < Options::kMaxLineSigmaPx,
                  "--sigma must be between ", Options::kMinLineSigmaPx, " and ",
                  Options::kMaxLineSigmaPx, " px, got ", detector.line_sigma_px);
  UWS_USAGE_CHECK(scan == "rows" || scan == "cols" || scan == "auto",
                  "--scan must be rows, cols or auto");
  UWS_USAGE_CHECK(channel == "red" || channel == "green" || channel == "blue" || channel == "auto",
                  "--channel must be red, green, blue or auto");
  UWS_USAGE_CHECK(albedo == "red" || albedo == "green" || albedo == "blue" || albedo == "none" ||
                      albedo == "auto",
                  "--albedo must be red, green, blue, none or auto");
  UWS_USAGE_CHECK(dataset_dir.empty() != images_dir.empty(), "give either --dataset or --images");
  UWS_USAGE_CHECK(!profiles_csv || rig_path || !dataset_dir.empty(),
                  "--profiles needs a rig (--rig or --dataset)");
  detector.Check();
}

bool LaserLineIsVertical(const Camera& camera, const Rigid3d& camera_from_laser) {
  double du = 0.0, dv = 0.0;
  for (double z : {1.0, 2.0, 3.0}) {
    const auto a = camera.Project(camera_from_laser * Eigen::Vector3d(-0.1 * z, 0.0, z));
    const auto b = camera.Project(camera_from_laser * Eigen::Vector3d(0.1 * z, 0.0, z));
    if (!a || !b) continue;
    du += std::abs(b->x() - a->x());
    dv += std::abs(b->y() - a->y());
  }
  return dv >= du;
}

namespace {

cv::Mat OverlayImage(const cv::Mat& image, laser::ColourLayout layout,
                     const laser::Detection& detection) {
  cv::Mat bgr;
  cv::Mat eight = image;
  if (image.depth() == CV_16U) image.convertTo(eight, CV_8U, 1.0 / 256.0);
  switch (layout) {
    case laser::ColourLayout::kBgr:
      bgr = eight.clone();
      break;
    case laser::ColourLayout::kMono:
      cv::cvtColor(eight, bgr, cv::COLOR_GRAY2BGR);
      break;
    // OpenCV names Bayer codes by the second row's pattern start.
    case laser::ColourLayout::kBayerRggb:
      cv::cvtColor(eight, bgr, cv::COLOR_BayerBG2BGR);
      break;
    case laser::ColourLayout::kBayerBggr:
      cv::cvtColor(eight, bgr, cv::COLOR_BayerRG2BGR);
      break;
    case laser::ColourLayout::kBayerGrbg:
      cv::cvtColor(eight, bgr, cv::COLOR_BayerGB2BGR);
      break;
    case laser::ColourLayout::kBayerGbrg:
      cv::cvtColor(eight, bgr, cv::COLOR_BayerGR2BGR);
      break;
  }
  for (const auto& p : detection.points) {
    const int u = static_cast<int>(std::lround(p.u)), v = static_cast<int>(std::lround(p.v));
    if (u >= 0 && v >= 0 && u < bgr.cols && v < bgr.rows) bgr.at<cv::Vec3b>(v, u) = {255, 0, 255};
  }
  return bgr;
}

void WriteImageAtomic(const fs::path& path, const cv::Mat& image) {
  std::vector<uchar> buffer;
  UWS_CHECK(cv::imencode(path.extension().string(), image, buffer), path.string(),
            ": cannot encode");
  AtomicFile file(path, /*binary=*/true);
  file.stream().write(reinterpret_cast<const char*>(buffer.data()), buffer.size());
  file.Commit();
}

// The outputs must not overwrite what is read: overlays written into the
// images' own folder replaced the frames with their drawings, and an --out
// or --profiles onto frames.csv or rig.yaml would replace the dataset's.
void CheckOutputsSpareInputs(const LaserDetectJob& job, const std::vector<fs::path>& images) {
  if (job.overlay_dir) {
    for (const fs::path& image : images) {
      UWS_USAGE_CHECK(!SameExistingPath(image.parent_path(), *job.overlay_dir), "--overlay ",
                      job.overlay_dir->string(), " is the folder of the images (", image.string(),
                      "): the overlays would overwrite them");
    }
  }
  std::vector<fs::path> inputs = images;
  if (!job.dataset_dir.empty()) {
    inputs.push_back(job.dataset_dir / "frames.csv");
    inputs.push_back(job.dataset_dir / "rig.yaml");
  }
  if (job.rig_path) inputs.push_back(*job.rig_path);
  RefuseOutputOntoInput("--out", job.detections_csv, inputs);
  if (job.profiles_csv) RefuseOutputOntoInput("--profiles", *job.profiles_csv, inputs);
}

}  // namespace

LaserDetectSummary RunLaserDetect(const LaserDetectJob& job) {
  InterruptibleScope interruptible;
  job.Check();
  const auto start = std::chrono::steady_clock::now();
  // Frames: a dataset's frames.csv (with servo angles) or a folder's images.
  std::vector<fs::path> images;
  std::vector<int> indices;
  std::vector<double> angles;
  std::vector<bool> laser_off;  // interleaved scans (frames.csv's laser_on): no line to find
  std::optional<Rig> rig;
  if (!job.dataset_dir.empty()) {
    rig = ReadRigYaml(job.dataset_dir / "rig.yaml");
    const auto records = ReadFramesCsv(job.dataset_dir / "frames.csv");
    UWS_CHECK(!records.empty(), (job.dataset_dir / "frames.csv").string(), ": no frames");
    for (const auto& record : records) {
      images.push_back(job.dataset_dir / record.file);
      indices.push_back(record.index);
      angles.push_back(record.laser_angle_rad.value_or(0.0));
      laser_off.push_back(record.LaserOff());
    }
  } else {
    images = ListImageFiles(job.images_dir);
    for (size_t i = 0; i < images.size(); ++i) indices.push_back(static_cast<int>(i));
    angles.assign(images.size(), 0.0);
    laser_off.assign(images.size(), false);
    if (job.rig_path) rig = ReadRigYaml(*job.rig_path);
  }
  const Camera* camera = rig ? &rig->CameraByName(job.camera_name) : nullptr;
  const LineProjector* laser =
      rig && !rig->lasers.empty() ? &rig->LaserByName(job.laser_name) : nullptr;
  UWS_CHECK(!job.profiles_csv || laser, "--profiles needs a laser in the rig");
  size_t camera_index = 0, laser_index = 0;
  if (rig) {
    camera_index = camera - rig->cameras.data();
    if (laser) laser_index = laser - rig->lasers.data();
  }
  const Rigid3d camera_from_laser =
      laser ? rig->CameraFromLaser(camera_index, laser_index) : Rigid3d();

  laser::DetectorOptions options = job.detector;
  if (job.scan != "auto")
    options.scan_rows = job.scan == "rows";
  else if (camera && laser)
    options.scan_rows = LaserLineIsVertical(*camera, camera_from_laser);
  if (job.channel == "red")
    options.laser_channel = laser::kRed;
  else if (job.channel == "green")
    options.laser_channel = laser::kGreen;
  else if (job.channel == "blue")
    options.laser_channel = laser::kBlue;
  else if (laser)
    options.laser_channel = laser::ChannelForWavelength(laser->wavelength_nm);
  options.albedo_channel = job.albedo == "auto" ? laser::AlbedoChannelFor(options.laser_channel)
                                                : laser::ChannelFromName(job.albedo);
  options.make_mask = false;  // not written by this command
  CheckOutputsSpareInputs(job, images);
  std::optional<OutputFolder> overlays;
  if (job.overlay_dir) overlays.emplace(*job.overlay_dir);

  AtomicFile detections(job.detections_csv);
  detections.stream() << "frame,u,v,channel,strength\n";
  std::optional<AtomicFile> profiles;
  if (job.profiles_csv) {
    profiles.emplace(*job.profiles_csv);
    profiles->stream() << "frame,x,y,z\n";
  }
  char line[160];
  LaserDetectSummary summary;
  bool pose_checked = false;
  laser::ClippedScene clipped_total;
  ProgressBar progress("laser detect", static_cast<long>(images.size()), !job.quiet);
  for (size_t i = 0; i < images.size(); ++i) {
    const size_t frame = static_cast<size_t>(indices[i]);
    ++summary.frames;
    if (laser_off[i]) {
      ++summary.frames_laser_off;
      progress.Update(static_cast<long>(i) + 1);
      continue;
    }
    cv::Mat image = cv::imread(images[i].string(), cv::IMREAD_UNCHANGED);
    if (image.empty()) {
      std::cerr << "uwscan: warning: " << images[i].string()
                << ": unreadable or truncated image, frame " << frame << " has no detections\n";
      ++summary.unreadable_frames;
      continue;
    }
    if (camera) {
      UWS_CHECK(image.cols == camera->width && image.rows == camera->height, images[i].string(),
                ": ", ImageSizeMismatch(*camera, image.cols, image.rows));
    }
    UWS_CHECK(image.depth() == CV_8U || image.depth() == CV_16U, images[i].string(),
              ": only 8- and 16-bit images are supported");
    PrepareFrame(&image, job.sample_bits, images[i]);
    const auto layout = laser::LayoutFor(camera ? camera->bayer : "none", image.channels());
    const bool first_read =
        summary.frames - summary.frames_laser_off - summary.unreadable_frames == 1;
    if (first_read) {
      summary.first_frame = InspectFrame(image, images[i], camera ? camera->bayer : "none",
                                         camera != nullptr, job.sample_bits);
    }
    const laser::Detection detection = laser::DetectLaserLine(image, layout, options);
    if (first_read) {
      const int seen = laser::OtherColourOfTheLine(image, layout, options, detection.points.size());
      const bool from_rig = laser && job.channel == "auto";
      if (seen >= 0) {
        summary.laser_colour_warning = laser::LaserColourWarning(
            seen, options.laser_channel, from_rig ? laser->wavelength_nm : 0.0);
      }
    }
    if (detection.points.empty()) ++summary.frames_without_line;
    const laser::ClippedScene clipped = laser::MeasureClipping(image, layout, options.laser_channel,
                                                               options.scan_rows, detection.points);
    summary.frames_with_clipped_scene += clipped.Share() >= laser::kClippedFrameShare;
    clipped_total.clipped += clipped.clipped;
    clipped_total.examined += clipped.examined;
    summary.points += detection.points.size();
    for (const auto& p : detection.points) {
      std::snprintf(line, sizeof(line), "%zu,%.4f,%.4f,%d,%.5g\n", frame, p.u, p.v, p.channel,
                    p.strength);
      detections.stream() << line;
    }
    if (profiles) {
      const double angle = angles[i];
      const auto profile = laser::TriangulateProfile(
          *camera, *laser, laser::CameraFromLaserAtAngle(camera_from_laser, angle),
          detection.points, static_cast<int>(frame));
      summary.profile_points += profile.points.size();
      summary.grazing_points += profile.grazing;
      summary.missed_points += profile.failed;
      if (!pose_checked && detection.points.size() >= laser::kPoseCheckPoints) {
        pose_checked = true;
        summary.laser_pose_inverse_fits =
            laser::InverseLaserPoseFits(*camera, *laser, camera_from_laser, angle, detection.points,
                                        profile, laser::kMaxRangeErrorPerPixel);
      }
      for (const auto& p : profile.points) {
        std::snprintf(line, sizeof(line), "%zu,%.7f,%.7f,%.7f\n", frame, p.point_in_camera.x(),
                      p.point_in_camera.y(), p.point_in_camera.z());
        profiles->stream() << line;
      }
    }
    if (job.overlay_dir) {
      WriteImageAtomic(*job.overlay_dir / (images[i].stem().string() + ".png"),
                       OverlayImage(image, layout, detection));
    }
    progress.Update(static_cast<long>(i) + 1);
    ThrowIfInterrupted();
  }
  progress.Finish();
  detections.Finish();  // both whole on disk before either takes its name
  if (profiles) profiles->Finish();
  detections.Commit();
  if (profiles) profiles->Commit();
  if (overlays) overlays->Keep();
  summary.clipped_scene_share = clipped_total.Share();
  summary.seconds = SecondsSince(start);
  return summary;
}

}  // namespace uwscan
