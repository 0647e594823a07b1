#include "uwscan/pipeline/other_cameras.h"

#include "uwscan/fusion/pose_provider.h"
#include "uwscan/io/rig_yaml.h"
#include "uwscan/pipeline/frame_reader.h"
#include "uwscan/pipeline/line_stage.h"
#include "uwscan/util/error.h"
#include "uwscan/util/interrupt.h"

namespace uwscan {
namespace fs = std::filesystem;

std::vector<FrameRecord> ReadFrames(const fs::path& dataset, int max_frames) {
  auto frames = ReadFramesCsv(dataset / "frames.csv");
  UWS_CHECK(!frames.empty(), (dataset / "frames.csv").string(), ": no frames");
  if (max_frames > 0 && static_cast<int>(frames.size()) > max_frames) frames.resize(max_frames);
  // A missing image stops the scan: say so before, not minutes into it.
  size_t missing = 0;
  const FrameRecord* first_missing = nullptr;
  for (const FrameRecord& frame : frames) {
    std::error_code error;
    if (fs::is_regular_file(dataset / frame.file, error)) continue;
    if (!first_missing) first_missing = &frame;
    ++missing;
  }
  UWS_CHECK(missing == 0, (dataset / first_missing->file).string(), ": no such image (frame ",
            first_missing->index, " of frames.csv", missing > 1 ? ", and " : "",
            missing > 1 ? std::to_string(missing - 1) + " more" : std::string(), ")");
  return frames;
}

std::vector<OtherCamera> FindOtherCameras(const fs::path& dataset, const Rig& rig,
                                          size_t main_camera, int max_frames) {
  std::vector<OtherCamera> others;
  for (size_t c = 0; c < rig.cameras.size(); ++c) {
    const fs::path folder = dataset / rig.cameras[c].name;
    if (c == main_camera || !fs::exists(folder / "frames.csv")) continue;
    OtherCamera other{folder, ReadFrames(folder, max_frames), ReadRigYaml(folder / "rig.yaml"),
                      rig.CameraFromCamera(main_camera, c)};
    UWS_CHECK(other.rig.cameras.front().name == rig.cameras[c].name, (folder / "rig.yaml").string(),
              ": lists camera '", other.rig.cameras.front().name,
              "' first, but the folder holds camera '", rig.cameras[c].name, "''s images");
    others.push_back(std::move(other));
  }
  return others;
}

struct OtherCameraStages::Stage {
  Stage(const ReconstructJob& job, const OtherCamera& other,
        std::optional<std::chrono::steady_clock::time_point> live_from,
        std::optional<double> max_lag_s)
      : camera(other),
        line_stage(job, other.folder, other.rig.cameras.front(), other.rig.lasers.front(),
                   other.rig.CameraFromLaser(0, 0), other.frames, &line_report),
        trajectory(job.out / ("trajectory_" + other.rig.cameras.front().name + ".tum")),
        reader(other.frames, &line_stage, nullptr, live_from, max_lag_s) {
    camera_report.name = other.rig.cameras.front().name;
    camera_report.laser = other.rig.lasers.front().name;
  }
  const OtherCamera& camera;
  // The line stage's counts: its own, as it runs on its own thread
  // (AddFurtherCameraLineCounts adds them to the run's at the end).
  ReconstructReport line_report;
  LineStage line_stage;
  TumWriter trajectory;
  FrameReader reader;  // last: its thread stops before the stage it reads with goes
  CameraReport camera_report;
  size_t next = 0;  // the next frame to take
};

OtherCameraStages::OtherCameraStages(const ReconstructJob& job,
                                     const std::vector<OtherCamera>& others,
                                     std::optional<std::chrono::steady_clock::time_point> live_from,
                                     std::optional<double> max_lag_s) {
  for (const OtherCamera& other : others)
    stages_.push_back(std::make_unique<Stage>(job, other, live_from, max_lag_s));
}

OtherCameraStages::~OtherCameraStages() = default;

void OtherCameraStages::Place(const std::vector<StampedPose>& main_poses,
                              const Rigid3d& first_main_pose, double max_gap_s, bool all,
                              const AddProfile& add_profile, const FrameDone& frame_done) {
  if (main_poses.empty() && !all) return;
  for (const auto& stage : stages_) {
    const std::vector<FrameRecord>& frames = stage->camera.frames;
    const Rigid3d& main_from_camera = stage->camera.main_from_camera;
    for (; stage->next < frames.size(); ++stage->next) {
      const FrameRecord& record = frames[stage->next];
      if (!all && record.timestamp_s > main_poses.back().timestamp_s) break;
      ReadFrame frame = stage->reader.Get(stage->next);
      CameraReport& report = stage->camera_report;
      if (frame.dropped) {  // the live run fell behind
        ++report.frames_dropped_live;
        frame_done(record.timestamp_s, false);
        ThrowIfInterrupted();
        continue;
      }
      ++report.frames;
      if (!frame.detection.points.empty()) ++report.frames_with_line;
      const auto main_pose = fusion::InterpolatePose(main_poses, record.timestamp_s, max_gap_s);
      if (main_pose) {
        const Rigid3d pose = *main_pose * main_from_camera;
        stage->line_stage.SetPose(record.index, pose);
        stage->trajectory.Add({record.timestamp_s, pose});
        add_profile(frame.profile, record.index, pose, first_main_pose * main_from_camera);
        report.points += static_cast<long>(frame.profile.points.size());
      } else {
        ++report.frames_without_pose;
      }
      frame_done(record.timestamp_s, main_pose.has_value());
      ThrowIfInterrupted();
    }
  }
}

void OtherCameraStages::Finish(ReconstructReport* report) {
  for (const auto& stage : stages_) {
    stage->trajectory.Finish();
    report->other_cameras.push_back(stage->camera_report);
    AddFurtherCameraLineCounts(stage->line_report, report);
  }
}

void OtherCameraStages::Commit() {
  for (const auto& stage : stages_) stage->trajectory.Commit();
}

double OtherCameraStages::seconds_waiting() const {
  double seconds = 0.0;
  for (const auto& stage : stages_) seconds += stage->reader.seconds_waiting();
  return seconds;
}

}  // namespace uwscan
