#include "uwscan/pipeline/reconstruct.h"

#include <unistd.h>

#include <chrono>
#include <future>
#include <iostream>
#include <map>

#include "uwscan/fusion/self_referenced.h"
#include "uwscan/io/dataset.h"
#include "uwscan/io/image.h"
#include "uwscan/io/ply.h"
#include "uwscan/io/rig_yaml.h"
#include "uwscan/io/tum.h"
#include "uwscan/laser/profile.h"
#include "uwscan/laser/sweep_filter.h"
#include "uwscan/pipeline/laser_detect.h"
#include "uwscan/util/atomic_file.h"
#include "uwscan/util/error.h"
#include "uwscan/util/progress.h"

namespace uwscan {
namespace fs = std::filesystem;

namespace {

double Seconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

uint8_t ToByte(float value) {
  return static_cast<uint8_t>(std::clamp(value * 255.0f, 0.0f, 255.0f));
}

}  // namespace

void ReconstructJob::Check() const {
  detector.Check();
  UWS_CHECK(max_frames >= 0, "--max-frames must be >= 0");
  UWS_CHECK(!out.empty(), "--out: empty output folder name");
}

std::vector<std::string> ReconstructReport::Warnings() const {
  std::vector<std::string> warnings;
  const auto percent = [](double part, double whole) {
    return std::to_string(static_cast<int>(std::lround(100.0 * part / std::max(whole, 1.0))));
  };
  const int frames_lit = frames - frames_laser_off;
  if (frames_lit > 0 && frames_with_line < 0.9 * frames_lit) {
    warnings.push_back("no laser line in " + percent(frames_lit - frames_with_line, frames_lit) +
                       " % of the frames with the laser on (turbid or dark water, the line out "
                       "of view or too weak): those frames add nothing to the cloud");
  }
  if (frames_with_line > 0 && scan_lines > 0 &&
      static_cast<double>(points) / frames_with_line < 0.5 * scan_lines) {
    warnings.push_back(
        "the profiles are short: " + std::to_string(points / std::max(frames_with_line, 1)) +
        " points per frame of " + std::to_string(scan_lines) +
        " scan lines (the line fades into the water or leaves the scene)");
  }
  if (frames_without_pose > 0) {
    warnings.push_back(std::to_string(frames_without_pose) + " frame(s) (" +
                       percent(frames_without_pose, frames) +
                       " %) got no pose and are left out of the cloud (tracking not started or "
                       "lost)");
  }
  const auto count = [&](const char* key) {
    return pose_details.is_object() && pose_details.contains(key) &&
                   pose_details[key].is_number_integer()
               ? pose_details[key].get<int>()
               : 0;
  };
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
                       " frame(s) line candidates on 5 % or more of the scan lines stayed put "
                       "while the laser swept (a stripe or a reflection in the scene that could "
                       "be taken for the line, or a surface the sheet grazes): ignored, " +
                       std::to_string(static_detections_removed) +
                       " in all (--keep-static-detections keeps them)");
  }
  if (count("implausible_poses_rejected") > 0) {
    warnings.push_back(std::to_string(count("implausible_poses_rejected")) +
                       " pose(s) moved faster than a vehicle can and were rejected");
  }
  return warnings;
}

nlohmann::json ReconstructReport::ToJson() const {
  return {{"frames", frames},
          {"warnings", Warnings()},
          {"frames_with_line", frames_with_line},
          {"frames_laser_off", frames_laser_off},
          {"lines_detected_on_difference_images", frames_on_difference},
          {"frames_without_pose", frames_without_pose},
          {"points", points},
          {"points_uncompensated", points_uncompensated},
          {"triangulation_failures", triangulation_failures},
          {"static_candidates_ignored", static_detections_removed},
          {"points_dropped_on_albedo_edges", albedo_edge_points},
          {"frames_sweep_filter_restored", frames_sweep_filter_restored},
          {"pose_source", pose_source},
          {"pose", pose_details},
          {"timing_s",
           {{"total", seconds},
            {"laser_detection", seconds_detect},
            {"triangulation", seconds_triangulate},
            {"pose_estimation", seconds_pose},
            {"io", seconds_io}}},
          {"sequence_duration_s", sequence_duration_s},
          {"real_time_factor", RealTimeFactor()}};
}

ReconstructReport RunReconstruct(const ReconstructJob& job,
                                 std::unique_ptr<fusion::PoseProvider> provider) {
  job.Check();
  const auto start = std::chrono::steady_clock::now();
  const Rig rig = ReadRigYaml(job.dataset / "rig.yaml");
  const Camera& camera = rig.CameraByName(job.camera_name);
  const LineProjector& laser = rig.LaserByName(job.laser_name);
  const size_t camera_index = &camera - rig.cameras.data();
  const size_t laser_index = &laser - rig.lasers.data();
  const Rigid3d camera_from_laser = rig.CameraFromLaser(camera_index, laser_index);
  auto frames = ReadFramesCsv(job.dataset / "frames.csv");
  UWS_CHECK(!frames.empty(), (job.dataset / "frames.csv").string(), ": no frames");
  if (job.max_frames > 0 && static_cast<int>(frames.size()) > job.max_frames)
    frames.resize(job.max_frames);

  laser::DetectorOptions detector = job.detector;
  detector.scan_rows = LaserLineIsVertical(camera, camera_from_laser);
  detector.laser_channel = laser::ChannelForWavelength(laser.wavelength_nm);
  detector.albedo_channel =
      job.drop_albedo_edges ? laser::AlbedoChannelFor(detector.laser_channel) : -1;
  detector.make_mask = true;

  if (!provider && job.poses_file) {
    provider = std::make_unique<fusion::TrajectoryPoseProvider>(ReadTum(*job.poses_file),
                                                                job.poses_file->string());
  }
  if (!provider) {
    provider = std::make_unique<fusion::SelfReferencedPoseProvider>(camera, detector.laser_channel,
                                                                    job.self_referenced);
  }

  std::error_code error;
  fs::create_directories(job.out, error);
  UWS_CHECK(!error, job.out.string(), ": cannot create output folder: ", error.message());
  PlyStreamWriter cloud(job.out / "cloud.ply");
  PlyStreamWriter uncompensated(job.out / "cloud_uncompensated.ply");
  TumWriter trajectory(job.out / "trajectory.tum");

  ReconstructReport report;
  report.pose_source = provider->Name();
  report.scan_lines = detector.scan_rows ? camera.height : camera.width;
  std::optional<laser::SweepFilter> sweep_filter;
  // The line in one frame; on servo scans, candidates standing where
  // candidates stood while the sheet turned are a stripe or reflection, not
  // the line (§5.5), and where nearly all would go (the line runs along a
  // stripe) only what stands exactly where the stripe stood is left out.
  const auto detect_line = [&](const cv::Mat& image, const FrameRecord& record) {
    laser::DetectorOptions options = detector;
    const bool sweeping = sweep_filter && record.laser_angle_rad;
    if (sweeping) {
      sweep_filter->Begin(record.index, *record.laser_angle_rad);
      options.exclude_candidate = sweep_filter->Predicate();
      options.exclude_candidate_on_restore = sweep_filter->Predicate(/*strict=*/true);
      options.keep_candidates = true;
    }
    laser::Detection detection =
        laser::DetectLaserLine(image, laser::LayoutFor(camera.bayer, image.channels()), options);
    if (sweeping) {
      sweep_filter->End(detection.candidates);
      detection.candidates = {};
    }
    return detection;
  };
  if (job.sweep_filter) {
    laser::SweepFilterOptions sweep;
    sweep.scan_rows = detector.scan_rows;
    sweep.focal_px = detector.scan_rows ? camera.intrinsics[0] : camera.intrinsics[1];
    sweep_filter.emplace(sweep);
    // The first frames have no earlier frame the sheet has turned far
    // enough from: remember the candidates of the first later frame that
    // is (a fraction of a second ahead, the platform has hardly moved), so
    // that a stripe is recognised from the first frame on. Interleaved
    // scans need no such help (their difference images hold no stripe).
    const bool interleaved = !frames.empty() && frames.front().laser_on.has_value();
    if (!interleaved && !frames.empty() && frames.front().laser_angle_rad) {
      const double start = *frames.front().laser_angle_rad;
      for (size_t k = 1; k < frames.size() && k <= size_t(sweep.max_lag_frames); ++k) {
        if (!frames[k].laser_angle_rad ||
            sweep.focal_px * std::abs(*frames[k].laser_angle_rad - start) <
                2.0 * sweep.min_expected_shift_px) {
          continue;
        }
        const cv::Mat ahead = ReadImage(job.dataset / frames[k].file);
        if (ahead.cols != camera.width || ahead.rows != camera.height) break;  // reported later
        detect_line(ahead, frames[k]);  // remembered by the filter
        break;
      }
    }
  }
  report.sequence_duration_s =
      frames.size() > 1
          ? frames.back().timestamp_s - frames.front().timestamp_s +
                (frames.back().timestamp_s - frames.front().timestamp_s) / (frames.size() - 1)
          : 0.0;
  ProgressBar progress("reconstruct", static_cast<long>(frames.size()), !job.quiet);
  // Profiles wait here until the provider reports their frame's pose.
  struct Pending {
    double timestamp_s;
    laser::Profile profile;
  };
  std::map<int, Pending> pending;
  std::optional<Rigid3d> first_pose;
  int frames_placed = 0;
  const auto place = [&](const std::vector<fusion::PoseUpdate>& updates) {
    for (const auto& update : updates) {
      const auto it = pending.find(update.frame);
      if (it == pending.end()) continue;
      if (!first_pose) first_pose = update.world_from_camera;
      trajectory.Add({it->second.timestamp_s, update.world_from_camera});
      ++frames_placed;
      const Rigid3d& placed = job.motion_compensation ? update.world_from_camera : *first_pose;
      for (const auto& p : it->second.profile.points) {
        CloudPoint point;
        point.intensity = p.strength;
        point.red = point.green = point.blue = ToByte(p.strength * 4.0f);
        point.frame = update.frame;
        point.position = placed * p.point_in_camera;
        cloud.Add(point);
        point.position = *first_pose * p.point_in_camera;
        uncompensated.Add(point);
      }
      report.points += static_cast<long>(it->second.profile.points.size());
      report.points_uncompensated += static_cast<long>(it->second.profile.points.size());
      pending.erase(pending.begin(), std::next(it));  // earlier frames will not get a pose now
    }
  };
  // The next frame is read and decoded on a second thread while this one is
  // processed (a live camera delivers decoded frames; PNG decoding of a
  // dataset would otherwise take a third of the time).
  const auto read = [&](size_t i) { return ReadImage(job.dataset / frames[i].file); };
  std::future<cv::Mat> next_image;
  cv::Mat dark_image;  // the last laser-off frame of an interleaved scan
  size_t dark_frame = 0;
  if (!frames.empty()) next_image = std::async(std::launch::async, read, size_t{0});
  for (size_t i = 0; i < frames.size(); ++i) {
    const FrameRecord& record = frames[i];
    auto t = std::chrono::steady_clock::now();
    const cv::Mat image = next_image.get();  // rethrows a read error
    if (i + 1 < frames.size()) next_image = std::async(std::launch::async, read, i + 1);
    UWS_CHECK(image.cols == camera.width && image.rows == camera.height,
              (job.dataset / record.file).string(), ": image is ", image.cols, "x", image.rows,
              " but camera '", camera.name, "' is ", camera.width, "x", camera.height);
    report.seconds_io += Seconds(t);

    t = std::chrono::steady_clock::now();
    // Interleaved scans (frames.csv laser_on, thesis §5.4): nothing to detect
    // with the laser off; with it on, the line is found in the difference to
    // the previous (laser-off) frame, where the scene's own texture, a
    // painted stripe or the ambient light cancel.
    const bool laser_off = record.laser_on && !*record.laser_on;
    const bool difference = job.detect_on_difference && record.laser_on && !laser_off;
    laser::Detection detection;
    if (difference && (i == 0 || dark_image.empty() || dark_frame != i - 1)) {
      // No laser-off frame just before (the first frame): the line is not
      // looked for in the raw image, where the scene could pass for it.
    } else if (!laser_off) {
      if (difference) {
        cv::Mat lit_only;
        cv::subtract(image, dark_image, lit_only);  // saturates at 0
        detection = detect_line(lit_only, record);
        ++report.frames_on_difference;
      } else {
        detection = detect_line(image, record);
      }
      report.static_detections_removed += detection.stats.excluded_candidates;
      report.albedo_edge_points += detection.stats.albedo_edge_points;
      // Noise and texture peaks are ignored now and then on any scene; a
      // stripe or reflection shows on many scan lines of a frame.
      report.frames_with_static_detections +=
          detection.stats.excluded_candidates >= 0.05 * report.scan_lines;
      report.frames_sweep_filter_restored += detection.stats.exclusion_restored;
    } else {
      ++report.frames_laser_off;
      dark_image = image;
      dark_frame = i;
    }
    const std::vector<laser::LaserPoint>& line_points = detection.points;
    report.seconds_detect += Seconds(t);

    t = std::chrono::steady_clock::now();
    const double angle = record.laser_angle_rad.value_or(0.0);
    laser::Profile profile = laser::TriangulateProfile(
        camera, laser, laser::CameraFromLaserAtAngle(camera_from_laser, angle), line_points,
        record.index);
    report.triangulation_failures += profile.failed;
    report.seconds_triangulate += Seconds(t);

    t = std::chrono::steady_clock::now();
    fusion::FrameInput input{record.index, record.timestamp_s, image, &detection, &profile};
    const auto updates = provider->Add(input);
    report.seconds_pose += Seconds(t);

    t = std::chrono::steady_clock::now();
    ++report.frames;
    if (!detection.points.empty()) ++report.frames_with_line;
    pending.emplace(record.index, Pending{record.timestamp_s, std::move(profile)});
    place(updates);
    report.seconds_io += Seconds(t);
    progress.Update(static_cast<long>(i + 1));
  }
  place(provider->Finish());
  report.frames_without_pose = report.frames - frames_placed;
  progress.Finish();
  if (!first_pose) {
    report.pose_details = provider->Details();
    std::string why;
    for (const std::string& warning : report.Warnings()) why += "\n  " + warning;
    UWS_THROW(job.dataset.string(), ": no frame got a pose (", provider->Name(), ")",
              report.frames_with_line == 0
                  ? "; the self-referenced poses need the laser line to measure the scene"
                  : "",
              why);
  }
  report.pose_details = provider->Details();
  cloud.Close();
  uncompensated.Close();
  trajectory.Commit();
  report.seconds = Seconds(start);
  nlohmann::json json = report.ToJson();
  json["dataset"] = fs::absolute(job.dataset).string();
  json["motion_compensation"] = job.motion_compensation;
  WriteFileAtomic(job.out / "report.json", json.dump(2) + "\n");
  return report;
}

}  // namespace uwscan
