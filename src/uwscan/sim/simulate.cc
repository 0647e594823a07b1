#include "uwscan/sim/simulate.h"

#include <chrono>
#include <future>

#include "uwscan/io/dataset.h"
#include "uwscan/io/image.h"
#include "uwscan/io/rig_yaml.h"
#include "uwscan/io/tum.h"
#include "uwscan/sim/ins.h"
#include "uwscan/sim/scene_yaml.h"
#include "uwscan/util/atomic_file.h"
#include "uwscan/util/error.h"
#include "uwscan/util/interrupt.h"
#include "uwscan/util/progress.h"
#include "uwscan/util/stopwatch.h"

namespace uwscan::sim {
namespace {

namespace fs = std::filesystem;

void CreateFolder(const fs::path& path) {
  std::error_code error;
  fs::create_directories(path, error);
  UWS_CHECK(!error, path.string(), ": cannot create folder: ", error.message());
}

// A calibration set: a dataset folder of its own (rig.yaml, frames.csv,
// frames/, groundtruth.tum with world = the target's frame).
void WriteCalibrationSet(const CalibrationSet& set, const fs::path& folder, ProgressBar* progress,
                         long* done) {
  CreateFolder(folder / "frames");
  WriteRigYaml(folder / "rig.yaml", set.config.rig);
  const Renderer renderer(set.config);
  FramesCsvWriter frames(folder / "frames.csv", false);
  TumWriter truth(folder / "groundtruth.tum");
  for (size_t i = 0; i < set.views.size(); ++i) {
    const FrameState& state = set.views[i];
    const RenderedFrame frame = renderer.Render(state);
    const std::string file = FrameFileName(static_cast<int>(i));
    WritePng(folder / file, frame.image);
    frames.Add({static_cast<int>(i), static_cast<double>(i), file, std::nullopt, std::nullopt});
    truth.Add({static_cast<double>(i), state.world_from_camera});
    progress->Update(++*done);
    ThrowIfInterrupted();
  }
  frames.Commit();
  truth.Commit();
}

// The images and ground truth of one camera: frames/ + frames.csv,
// groundtruth.tum, laser_gt.csv and the INS log, all of this camera. Frame
// indices run on from camera to camera, so that they name a frame of the
// whole dataset (and a point of the merged cloud) uniquely.
void WriteSequence(const Scenario& scenario, size_t camera, const fs::path& folder,
                   ProgressBar* progress, long* done, SimulateResult* result) {
  const Renderer renderer(scenario.CameraConfig(camera));
  const Trajectory trajectory(scenario.motion);
  const bool with_angle = !renderer.config().lasers.empty();
  FramesCsvWriter frames(folder / "frames.csv", with_angle, scenario.laser_interleave);
  TumWriter truth(folder / "groundtruth.tum");
  LaserTruthWriter laser_truth(folder / "laser_gt.csv");
  const int first_index = static_cast<int>(camera) * scenario.frames;
  // Each image is compressed and written while the next one renders (a
  // tenth of a frame's time on one core); a write error comes out at the
  // next frame, or at the end.
  std::future<void> writing;
  for (int i = 0; i < scenario.frames; ++i) {
    const FrameState state = scenario.FrameAt(trajectory, i, camera);
    RenderedFrame frame = renderer.Render(state);
    const std::string file = FrameFileName(i);
    if (writing.valid()) writing.get();
    writing = std::async(
        std::launch::async,
        [path = folder / file, image = std::move(frame.image)] { WritePng(path, image); });
    std::optional<double> angle;
    if (with_angle) angle = state.laser_angles_rad.front();
    const int index = first_index + i;
    const double time = scenario.TimeOf(i, camera);
    frames.Add({index, time, file, angle, state.lasers_on});
    truth.Add({time, state.world_from_camera});
    for (const LaserPoint& point : renderer.LaserGroundTruth(state)) {
      laser_truth.Add({index, point.laser, point.pixel.x(), point.pixel.y(),
                       point.point_in_camera.x(), point.point_in_camera.y(),
                       point.point_in_camera.z()});
      ++result->laser_points;
    }
    progress->Update(++*done);
    ThrowIfInterrupted();
  }
  if (writing.valid()) writing.get();
  frames.Commit();
  truth.Commit();
  laser_truth.Commit();
  // What the vehicle's navigation would have logged (thesis §6.5), for
  // `uwscan reconstruct --poses ins.tum`: the same INS for every camera,
  // carried over through the rig.
  InsOptions ins;
  ins.seed = scenario.seed + 1000;
  const Rigid3d camera0_from_camera = scenario.config.rig.CameraFromCamera(0, camera);
  std::vector<StampedPose> log =
      SimulateIns(trajectory, 0.0, scenario.TimeOf(std::max(0, scenario.frames - 1)), ins);
  for (StampedPose& pose : log)
    pose.world_from_camera = pose.world_from_camera * camera0_from_camera;
  WriteTum(folder / "ins.tum", log);
}

}  // namespace

SimulateResult WriteDataset(const Scenario& scenario, const fs::path& out_dir, bool show_progress) {
  InterruptibleScope interruptible;
  const auto start = std::chrono::steady_clock::now();
  StagedFolder staged(out_dir);
  const fs::path& temp_dir = staged.path();
  CreateFolder(temp_dir / "frames");

  WriteRigYaml(temp_dir / "rig.yaml", scenario.config.rig);
  WriteSceneYaml(temp_dir / "scene.yaml", scenario);

  long total = static_cast<long>(scenario.frames * scenario.Cameras());
  for (const auto& set : scenario.calibration) total += static_cast<long>(set.views.size());
  ProgressBar progress("simulate " + scenario.name, total, show_progress);
  long done = 0;

  SimulateResult result;
  for (size_t camera = 0; camera < scenario.Cameras(); ++camera) {
    fs::path folder = temp_dir;
    if (camera > 0) {
      // Every further camera: a dataset of its own in a subfolder named
      // after it, its rig listing it (and its laser) first.
      const Rig rig = scenario.config.rig.Reordered(camera, camera);
      folder /= rig.cameras.front().name;
      CreateFolder(folder / "frames");
      WriteRigYaml(folder / "rig.yaml", rig);
      Scenario seen = scenario;
      seen.config = scenario.CameraConfig(camera);
      WriteSceneYaml(folder / "scene.yaml", seen);
    }
    WriteSequence(scenario, camera, folder, &progress, &done, &result);
  }
  for (const auto& set : scenario.calibration) {
    WriteCalibrationSet(set, temp_dir / "calib" / set.name, &progress, &done);
  }
  progress.Finish();

  staged.Commit();
  result.frames = static_cast<int>(scenario.frames * scenario.Cameras());
  result.seconds = SecondsSince(start);
  return result;
}

SimulateResult SimulateScenario(const std::string& name, const ScenarioOptions& options,
                                const fs::path& out_dir, bool progress) {
  return WriteDataset(MakeScenario(name, options), out_dir, progress);
}

}  // namespace uwscan::sim
