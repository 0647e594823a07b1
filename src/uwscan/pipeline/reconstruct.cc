#include "uwscan/pipeline/reconstruct.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <map>

#include "uwscan/fusion/self_referenced.h"
#include "uwscan/io/dataset.h"
#include "uwscan/io/ply.h"
#include "uwscan/io/rig_yaml.h"
#include "uwscan/io/tum.h"
#include "uwscan/io/tum_trajectory.h"
#include "uwscan/laser/profile.h"
#include "uwscan/pipeline/frame_reader.h"
#include "uwscan/pipeline/line_stage.h"
#include "uwscan/pipeline/other_cameras.h"
#include "uwscan/sim/scene_yaml.h"
#include "uwscan/util/atomic_file.h"
#include "uwscan/util/error.h"
#include "uwscan/util/interrupt.h"
#include "uwscan/util/json.h"
#include "uwscan/util/progress.h"
#include "uwscan/util/statistics.h"
#include "uwscan/util/stopwatch.h"

namespace uwscan {
namespace fs = std::filesystem;

namespace {

uint8_t ToByte(float value) {
  return static_cast<uint8_t>(std::clamp(value * 255.0f, 0.0f, 255.0f));
}

// The simulator's truth for --oracle-depths and --oracle-tracks (`flag`):
// scene and true trajectory.
std::shared_ptr<const fusion::SimulatorTruth> LoadSimulatorTruth(const fs::path& dataset,
                                                                 const std::string& flag) {
  UWS_CHECK(fs::exists(dataset / "scene.yaml"), (dataset / "scene.yaml").string(),
            ": missing: ", flag, " needs a simulated dataset with its scene");
  UWS_CHECK(fs::exists(dataset / "groundtruth.tum"), (dataset / "groundtruth.tum").string(),
            ": missing: ", flag, " needs the true trajectory");
  auto scenario = std::make_shared<sim::Scenario>(sim::LoadDatasetScenario(dataset));
  scenario->config.scene.Prepare();
  auto truth = std::make_shared<std::vector<StampedPose>>(ReadTum(dataset / "groundtruth.tum"));
  auto oracle = std::make_shared<fusion::SimulatorTruth>();
  oracle->true_pose = [truth](double timestamp_s) {
    return fusion::InterpolatePose(*truth, timestamp_s, 0.01);
  };
  oracle->intersect = [scenario](
                          const Eigen::Vector3d& origin,
                          const Eigen::Vector3d& direction) -> std::optional<Eigen::Vector3d> {
    const auto hit = scenario->config.scene.Intersect(origin, direction);
    if (!hit) return std::nullopt;
    return hit->point_world;
  };
  return oracle;
}

// --poses: the camera's poses from the external trajectory, put on the
// camera's clock and moved from the body it logs (an INS's) to the camera;
// the name says how it was read. A file that covers none of the frames'
// times (a log on another clock: epoch seconds against a camera's from 0) is
// refused before the frames are read, with the offset that would align the
// two starts.
std::unique_ptr<fusion::PoseProvider> ExternalPoses(const ReconstructJob& job,
                                                    const std::vector<FrameRecord>& frames,
                                                    ReconstructReport* report) {
  TumTrajectory trajectory = ReadTumTrajectory(*job.poses_file, 1e-6);
  std::vector<StampedPose>& poses = trajectory.poses;
  std::vector<std::pair<double, double>> gaps;  // no pose is interpolated across one
  for (const TrajectoryGap& gap : trajectory.gaps)
    gaps.emplace_back(gap.begin_s + job.poses_time_offset_s, gap.end_s + job.poses_time_offset_s);
  std::string name = job.poses_file->string();
  if (job.poses_time_offset_s != 0.0 || job.poses_body_from_camera) {
    for (StampedPose& pose : poses) {
      pose.timestamp_s += job.poses_time_offset_s;
      if (job.poses_body_from_camera)
        pose.world_from_camera = pose.world_from_camera * *job.poses_body_from_camera;
    }
    std::string how;
    if (job.poses_time_offset_s != 0.0)
      how = fmt::format("times {:+.6g} s", job.poses_time_offset_s);
    if (job.poses_body_from_camera)
      how += std::string(how.empty() ? "" : "; ") + "the camera in its body's frame";
    name += " (" + how + ")";
  }
  constexpr double kMaxExtrapolationS = 0.05;
  if (!poses.empty() && !frames.empty()) {
    const double first = poses.front().timestamp_s, last = poses.back().timestamp_s;
    const double frames_first = frames.front().timestamp_s;
    const double frames_last = frames.back().timestamp_s;
    UWS_CHECK(
        first - kMaxExtrapolationS <= frames_last && frames_first <= last + kMaxExtrapolationS,
        name, ": its poses (", fmt::format("{:.3f}-{:.3f} s", first, last),
        ") cover none of the frames' times (", job.dataset.string(), "/frames.csv, ",
        fmt::format("{:.3f}-{:.3f} s", frames_first, frames_last),
        "): a log on another clock? --poses-time-offset ",
        fmt::format("{:.6f}", frames_first - first + job.poses_time_offset_s),
        " would align the two starts");
    std::vector<double> steps;
    for (size_t i = 1; i < poses.size(); ++i)
      steps.push_back(poses[i].timestamp_s - poses[i - 1].timestamp_s);
    report->external_pose_step_s = steps.empty() ? 0.0 : Median(steps);
    report->external_poses_in_scan =
        static_cast<int>(std::count_if(poses.begin(), poses.end(), [&](const StampedPose& pose) {
          return pose.timestamp_s >= frames_first && pose.timestamp_s <= frames_last;
        }));
  }
  return std::make_unique<fusion::TrajectoryPoseProvider>(std::move(poses), name,
                                                          kMaxExtrapolationS, std::move(gaps));
}

// report.json's text for a run.
std::string ReportText(const ReconstructJob& job, const ReconstructReport& report) {
  nlohmann::json json = report.ToJson();
  json["dataset"] = fs::absolute(job.dataset).string();
  json["motion_compensation"] = job.motion_compensation;
  return json.dump(2) + "\n";
}

// report.json of a run into job.out.
void WriteReport(const ReconstructJob& job, const ReconstructReport& report) {
  WriteFileAtomic(job.out / "report.json", ReportText(job, report));
}

// A run after the first (a later pass, the run on half the image) failed
// or was interrupted before committing its outputs: those of the run
// before stand, whole, and `earlier` (its report, saying why there is no
// later one) replaces its report.json. An interruption is passed on,
// naming what stands (`whose`: "pass 1's").
ReconstructReport KeepEarlierRun(const ReconstructJob& job, const ReconstructReport& earlier,
                                 const Error& error, const std::string& whose) {
  WriteReport(job, earlier);
  if (const auto* interrupted = dynamic_cast<const Interrupted*>(&error)) {
    throw Interrupted(interrupted->signal(),
                      job.out.string() + " holds " + whose + " outputs (report.json says so)");
  }
  return earlier;
}

// What the self-referenced odometry of one pass measured, for the next.
struct MeasuredScene {
  std::shared_ptr<const fusion::SurfaceModel> surface;
  int first_frame = -1;
  double seconds = 0.0;                     // of this pass and those before it
  std::map<int, Rigid3d> poses;             // world_from_camera by frame index
  std::vector<fusion::PoseChange> changes;  // of this pass and those before it
};

// How far the poses moved from one pass to the next, rms over the frames
// both placed.
std::optional<fusion::PoseChange> PassChange(const std::map<int, Rigid3d>& before,
                                             const std::map<int, Rigid3d>& after) {
  std::vector<std::optional<Rigid3d>> was, is;
  for (const auto& [frame, pose] : after) {
    if (const auto it = before.find(frame); it != before.end()) {
      was.push_back(it->second);
      is.push_back(pose);
    }
  }
  return fusion::RmsPoseChange(was, is);
}

// One pass over the frames: writes the outputs and returns the report;
// `prior` (a later pass) starts the self-referenced odometry on the pass
// before's surface, `measured` receives this pass's. `pass` counts from 1
// (of `passes`, 0 while not known: auto).
// `retried` is the report of a first attempt this one runs again
// (ReconstructJob::retry_smaller_tracking), if any.
ReconstructReport RunPass(const ReconstructJob& job, std::unique_ptr<fusion::PoseProvider> provider,
                          int pass, int passes, const MeasuredScene* prior, MeasuredScene* measured,
                          const ReconstructReport* retried = nullptr) {
  const auto start = std::chrono::steady_clock::now();
  const fs::path rig_path = job.dataset / "rig.yaml";
  const Rig rig = ReadRigYaml(rig_path);
  UWS_CHECK(!rig.lasers.empty(), rig_path.string(),
            ": the rig has no laser, and reconstruct measures the scene with the laser line (a "
            "dataset for calibrating the camera alone, such as the aquarium scenario's, cannot "
            "be reconstructed)");
  const Camera& camera = rig.CameraByName(job.camera_name);  // errors name the rig's file
  const LineProjector& laser = rig.LaserByName(job.laser_name);
  const size_t camera_index = &camera - rig.cameras.data();
  const size_t laser_index = &laser - rig.lasers.data();
  UWS_CHECK(camera_index == 0 || !fs::exists(job.dataset / camera.name / "frames.csv"), "--camera ",
            camera.name, ": the images in ", job.dataset.string(), " are those of camera '",
            rig.cameras.front().name, "'; for camera '", camera.name, "' alone give --dataset ",
            (job.dataset / camera.name).string(), " (", job.dataset.string(),
            " itself uses every camera)");
  const Rigid3d camera_from_laser = rig.CameraFromLaser(camera_index, laser_index);
  const auto frames = ReadFrames(job.dataset, job.max_frames);
  ReconstructReport report;
  LineStage line_stage(job, job.dataset, camera, laser, camera_from_laser, frames, &report);
  const std::vector<OtherCamera> others =
      job.other_cameras && job.camera_name.empty()
          ? FindOtherCameras(job.dataset, rig, 0, job.max_frames)
          : std::vector<OtherCamera>{};

  if (!provider && job.poses_file) provider = ExternalPoses(job, frames, &report);
  const fusion::SelfReferencedPoseProvider* self_referenced = nullptr;
  if (!provider) {
    fusion::SelfReferencedOptions options = job.self_referenced;
    options.track_every = ResolveTrackEvery(job.track_every, frames);
    report.track_every = options.track_every;
    options.start_screen_every =
        ResolveStartScreenEvery(job.start_screen_every, options.track_every, frames);
    report.start_screen_every = options.start_screen_every;
    options.smoothing_half_window = ResolveSmoothingHalfWindow(job.smoothing_half_window, frames);
    report.smoothing_half_window = options.smoothing_half_window;
    options.odometry.async_bundle_adjustment =
        ResolveAsyncBundleAdjustment(job.async_bundle_adjustment, frames);
    report.async_bundle_adjustment = options.odometry.async_bundle_adjustment;
    const bool sweeps = LaserSweeps(frames);
    report.laser_sweeps = sweeps;
    options.use_line_ranges = job.line_ranges.value_or(!sweeps);
    options.contrast_sigma_fraction =
        job.contrast_scale.value_or(sweeps ? 0.0 : ReconstructJob::kFixedLaserContrastScale);
    report.contrast_scale = options.contrast_sigma_fraction;
    report.log_offset = options.log_offset_fraction;
    options.max_unsettled_start_refusals =
        job.unsettled_start_refusals.value_or(sweeps ? options.max_unsettled_start_refusals : 0);
    if (job.oracle_depths || job.oracle_tracks) {
      // Both oracles read the same truth: loaded (and the scene prepared) once.
      const auto truth = LoadSimulatorTruth(
          job.dataset, job.oracle_depths ? "--oracle-depths" : "--oracle-tracks");
      if (job.oracle_depths) options.depth_oracle = truth;
      if (job.oracle_tracks) options.track_oracle = truth;
    }
    if (prior) {
      options.prior_surface = prior->surface;
      options.prior_first_frame = prior->first_frame;
    }
    report.line_ranges = options.use_line_ranges;
    auto odometry = std::make_unique<fusion::SelfReferencedPoseProvider>(
        camera, line_stage.detector().laser_channel, options);
    self_referenced = odometry.get();
    provider = std::move(odometry);
  }

  PlyStreamWriter cloud(job.out / "cloud.ply");
  PlyStreamWriter uncompensated(job.out / "cloud_uncompensated.ply");
  TumWriter trajectory(job.out / "trajectory.tum");

  report.pose_source = provider->Name();
  if (job.oracle_depths)
    report.pose_source += " (feature depths from the simulator's truth: --oracle-depths)";
  if (job.oracle_tracks)
    report.pose_source += " (feature tracks from the simulator's truth: --oracle-tracks)";
  report.scan_lines = line_stage.ScanLines();
  const double frame_interval = MeanFrameInterval(frames);
  report.sequence_duration_s =
      frames.size() > 1 ? frames.back().timestamp_s - frames.front().timestamp_s + frame_interval
                        : 0.0;
  report.frame_gaps = FindFrameGaps(frames);
  long total_frames = static_cast<long>(frames.size());
  for (const auto& other : others) total_frames += static_cast<long>(other.frames.size());
  std::string label = "reconstruct";
  if (retried)
    label += ", again at " + std::to_string(job.self_referenced.max_tracking_width) + " px";
  if (pass > 1 || passes > 1) label += ", pass " + std::to_string(pass);
  if (passes > 1) label += " of " + std::to_string(passes);
  ProgressBar progress(label, total_frames, !job.quiet);
  long frames_done = 0;
  std::optional<Rigid3d> first_pose;
  std::vector<StampedPose> placed_poses;  // the main camera's, in time order
  // A profile into both clouds: placed with its pose, and with the first.
  const auto add_profile = [&](const laser::Profile& profile, int frame, const Rigid3d& pose,
                               const Rigid3d& unmoved) {
    const Rigid3d& placed = job.motion_compensation ? pose : unmoved;
    for (const auto& p : profile.points) {
      CloudPoint point;
      point.intensity = p.strength;
      point.red = point.green = point.blue = ToByte(p.strength * 4.0f);
      point.frame = frame;
      point.position = placed * p.point_in_camera;
      cloud.Add(point);
      point.position = unmoved * p.point_in_camera;
      uncompensated.Add(point);
    }
    report.points += static_cast<long>(profile.points.size());
    report.points_uncompensated += static_cast<long>(profile.points.size());
  };
  // Profiles wait here until the provider reports their frame's pose.
  struct Pending {
    double timestamp_s;
    laser::Profile profile;
  };
  std::map<int, Pending> pending;
  int frames_placed = 0;
  // A live run (the first pass only; ReconstructJob::live): frames are
  // delivered from now on at the camera's pace, and each placed frame's
  // (delivery time, lag) kept.
  std::optional<std::chrono::steady_clock::time_point> live_from;
  if (job.live && pass == 1 && !retried) live_from = std::chrono::steady_clock::now();
  std::vector<std::pair<double, double>> live_lags;
  // What a later pass starts from. The odometry's own surface when it
  // started from nothing; when it started from a prior, that surface holds
  // the prior's samples too (most of its bounded sample of the scene), so
  // this pass's profiles are gathered alone, placed with its poses.
  std::shared_ptr<fusion::SurfaceModel> placed_surface;
  if (measured && prior) {
    placed_surface =
        std::make_shared<fusion::SurfaceModel>(camera, Rigid3d(), job.self_referenced.surface);
  }
  const auto place = [&](const std::vector<fusion::PoseUpdate>& updates) {
    for (const auto& update : updates) {
      const auto it = pending.find(update.frame);
      if (it == pending.end()) continue;
      if (!first_pose) first_pose = update.world_from_camera;
      trajectory.Add({it->second.timestamp_s, update.world_from_camera});
      placed_poses.push_back({it->second.timestamp_s, update.world_from_camera});
      if (measured) measured->poses[update.frame] = update.world_from_camera;
      line_stage.SetPose(update.frame, update.world_from_camera);
      ++frames_placed;
      if (live_from) {
        const double delivered_s = it->second.timestamp_s - frames.front().timestamp_s;
        live_lags.emplace_back(delivered_s, SecondsSince(*live_from) - delivered_s);
      }
      add_profile(it->second.profile, update.frame, update.world_from_camera, *first_pose);
      if (placed_surface) placed_surface->AddProfile(update.world_from_camera, it->second.profile);
      pending.erase(pending.begin(), std::next(it));  // earlier frames will not get a pose now
    }
  };
  FrameReader reader(frames, &line_stage, provider.get(), live_from,
                     live_from ? job.live_max_lag_s : std::nullopt);
  if (job.live_max_lag_s) report.live_max_lag_s = *job.live_max_lag_s;
  // The further cameras' frames join the cloud as the main trajectory
  // reaches their times (for a live run: as they are delivered, give or
  // take the main poses' delay). That is held back by the pose smoothing's
  // window, so their readers may lag that much more before they drop
  // frames: they drop for a machine that falls behind, not for the window.
  std::optional<double> other_max_lag_s;
  if (live_from && job.live_max_lag_s) {
    other_max_lag_s =
        *job.live_max_lag_s + report.smoothing_half_window * report.track_every * frame_interval;
  }
  OtherCameraStages other_stages(job, others, live_from, other_max_lag_s);
  const auto place_others = [&](bool all) {
    if (!first_pose) return;
    other_stages.Place(placed_poses, *first_pose, 1.5 * frame_interval, all, add_profile,
                       [&](double timestamp_s, bool placed) {
                         if (placed && live_from) {
                           const double delivered_s = timestamp_s - frames.front().timestamp_s;
                           live_lags.emplace_back(delivered_s,
                                                  SecondsSince(*live_from) - delivered_s);
                         }
                         progress.Update(++frames_done);
                       });
  };
  for (size_t i = 0; i < frames.size(); ++i) {
    const FrameRecord& record = frames[i];
    ReadFrame frame = reader.Get(i);
    if (frame.dropped) {  // the live run fell behind
      ++report.frames_dropped_live;
      progress.Update(++frames_done);
      ThrowIfInterrupted();
      continue;
    }
    const cv::Mat& image = frame.image;
    laser::Detection& detection = frame.detection;
    laser::Profile& profile = frame.profile;

    auto t = std::chrono::steady_clock::now();
    fusion::FrameInput input{record.index, record.timestamp_s,
                             image,        &detection,
                             &profile,     frame.prepared ? &*frame.prepared : nullptr};
    const auto updates = provider->Add(input);
    for (const auto& raw : provider->Preliminary())
      line_stage.SetPose(raw.frame, raw.world_from_camera);
    report.seconds_pose += SecondsSince(t);

    t = std::chrono::steady_clock::now();
    ++report.frames;
    if (!detection.points.empty()) ++report.frames_with_line;
    pending.emplace(record.index, Pending{record.timestamp_s, std::move(profile)});
    place(updates);
    place_others(false);
    report.seconds_io += SecondsSince(t);
    progress.Update(++frames_done);
    ThrowIfInterrupted();
  }
  place(provider->Finish());
  report.seconds_waiting_for_images += reader.seconds_waiting();
  report.seconds_io += reader.seconds_waiting();
  if (self_referenced) {
    const std::shared_ptr<const fusion::SurfaceModel> surface =
        placed_surface ? placed_surface : self_referenced->MeasuredSurface();
    report.surface_in_front = surface && surface->HasFrontSurface();
    if (measured) {
      measured->surface = surface;
      measured->first_frame = self_referenced->FirstFrameWithPose();
    }
  }
  report.frames_without_pose = report.frames - frames_placed;
  if (!first_pose) {
    progress.Finish();
    report.pose_details = provider->Details();
    std::string why;
    for (const std::string& warning : report.Warnings()) why += "\n  " + warning;
    UWS_THROW(job.dataset.string(), ": no frame got a pose (", provider->Name(), ")",
              report.frames_with_line == 0
                  ? "; the self-referenced poses need the laser line to measure the scene"
                  : "",
              why);
  }

  place_others(true);  // the further cameras' frames after the main trajectory's end
  other_stages.Finish(&report);
  if (live_from) report.live_lag = SummarizeLiveLag(live_lags, report.sequence_duration_s);
  report.seconds_waiting_for_images += other_stages.seconds_waiting();
  report.seconds_io += other_stages.seconds_waiting();
  progress.Finish();
  report.pose_details = provider->Details();
  cloud.Finish();
  uncompensated.Finish();
  trajectory.Finish();
  report.passes = pass;
  if (prior && measured) {
    report.pass_changes = prior->changes;
    if (const auto change = PassChange(prior->poses, measured->poses))
      report.pass_changes.push_back(*change);
    if (passes == 0 && !report.pass_changes.empty()) {
      const fusion::PoseChange& last = report.pass_changes.back();
      report.passes_settled =
          last.moved_m < job.passes_settled_m && last.turned_deg < job.passes_settled_deg;
      report.passes_settled_within = {job.passes_settled_m, job.passes_settled_deg};
    }
  }
  if (measured) measured->changes = report.pass_changes;
  report.seconds_earlier_passes = prior ? prior->seconds : retried ? retried->seconds : 0.0;
  if (retried) {
    report.tracking_retried_from_width = retried->pose_details.value("tracked_image_width", 0);
    report.retried_start_change_mm =
        NumberAt(retried->pose_details, "start_last_change_mm").value_or(0.0);
  }
  report.seconds = SecondsSince(start) + report.seconds_earlier_passes;
  if (measured) measured->seconds = report.seconds;
  // Every output is whole on disk before any takes its final name (a disk
  // that fills up on the last leaves none), report.json last.
  StagedFiles report_file;
  report_file.Add(job.out / "report.json", ReportText(job, report));
  cloud.Commit();
  uncompensated.Commit();
  trajectory.Commit();
  other_stages.Commit();
  report_file.Commit();
  return report;
}

}  // namespace

std::vector<fs::path> ReconstructImages(const ReconstructJob& job) {
  UWS_CHECK(fs::is_directory(job.dataset), job.dataset.string(), ": no such dataset folder");
  std::vector<fs::path> files;
  for (const FrameRecord& frame : ReadFrames(job.dataset, job.max_frames))
    files.push_back(job.dataset / frame.file);
  if (job.other_cameras && job.camera_name.empty()) {
    const Rig rig = ReadRigYaml(job.dataset / "rig.yaml");
    for (const OtherCamera& other : FindOtherCameras(job.dataset, rig, 0, job.max_frames)) {
      for (const FrameRecord& frame : other.frames) files.push_back(other.folder / frame.file);
    }
  }
  return files;
}

ReconstructReport RunReconstruct(const ReconstructJob& job,
                                 std::unique_ptr<fusion::PoseProvider> provider) {
  job.Check();
  UWS_CHECK(fs::is_directory(job.dataset), job.dataset.string(), ": no such dataset folder");
  // An --out that holds the --poses file (a trajectory.tum from an earlier
  // run) or is the dataset would have it replaced by this run's outputs.
  std::vector<fs::path> inputs = {job.dataset / "frames.csv", job.dataset / "rig.yaml",
                                  job.dataset / "groundtruth.tum"};
  if (job.poses_file) inputs.push_back(*job.poses_file);
  for (const char* output :
       {"trajectory.tum", "report.json", "cloud.ply", "cloud_uncompensated.ply"})
    RefuseOutputOntoInput("--out", job.out / output, inputs);
  InterruptibleScope interruptible;
  OutputFolder out(job.out);  // removed again if the run fails and left it empty
  if (provider || job.poses_file) {
    ReconstructReport report = RunPass(job, std::move(provider), 1, 1, nullptr, nullptr);
    out.Keep();
    return report;
  }
  MeasuredScene measured;
  MeasuredScene* measure = job.passes == 1 ? nullptr : &measured;
  ReconstructReport report = RunPass(job, nullptr, 1, job.passes, nullptr, measure);
  out.Keep();  // the first pass's outputs stand
  // Auto: more passes only where the first found a surface in front of the
  // scene's main one, whose depths the features had to guess until the
  // laser reached it.
  if (job.passes != 1 && measured.surface &&
      (job.passes > 1 || measured.surface->HasFrontSurface())) {
    const bool automatic = job.passes == 0;
    const int passes = automatic ? ReconstructJob::kMaxPasses : job.passes;
    for (int pass = 2; pass <= passes; ++pass) {
      MeasuredScene next;
      try {
        report = RunPass(job, nullptr, pass, automatic ? 0 : passes, &measured, &next);
      } catch (const Error& e) {
        report.later_pass_failed = e.what();
        return KeepEarlierRun(job, report, e, fmt::format("pass {}'s", pass - 1));
      }
      measured = std::move(next);
      if (!automatic || pass < ReconstructJob::kMinAutoPasses) continue;
      const auto& changes = report.pass_changes;
      const bool converging = pass <= ReconstructJob::kMinAutoPasses || changes.size() < 2 ||
                              changes.back().moved_m <
                                  job.passes_converging_ratio * changes[changes.size() - 2].moved_m;
      if (report.passes_settled != false || !converging) break;
    }
    return report;
  }
  // The first pass is the last, and its start had not settled: once more
  // on a smaller tracked image, whose outputs replace the first attempt's.
  // (Where more passes follow, they start again on the surface the first
  // measured over the whole scan, and a hull's shaft needs the full image:
  // on the simulator's hulls, whose first start often moves a few
  // centimetres, half the image made the shaft worse on 4 of the 5 it
  // took; BENCHMARKS.md, "The run on half the image and the hulls".)
  const std::optional<int> width = report.SmallerTrackingWidth();
  if (!width || !job.retry_smaller_tracking) return report;
  ReconstructJob smaller = job;
  smaller.self_referenced.max_tracking_width = *width;
  const ReconstructReport first = report;
  try {
    return RunPass(smaller, nullptr, 1, job.passes, nullptr, nullptr, &first);
  } catch (const Error& e) {
    // Nothing placed on half the image (say), or Ctrl-C.
    report.tracking_retry_failed = e.what();
    return KeepEarlierRun(job, report, e, "the first run's");
  }
}

}  // namespace uwscan
