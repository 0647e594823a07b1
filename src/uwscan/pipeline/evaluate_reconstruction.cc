#include "uwscan/pipeline/evaluate_reconstruction.h"

#include <algorithm>
#include <cmath>

#include "uwscan/io/dataset.h"
#include "uwscan/io/ply.h"
#include "uwscan/io/tum.h"
#include "uwscan/sim/scene_yaml.h"
#include "uwscan/util/error.h"
#include "uwscan/util/statistics.h"

namespace uwscan {
namespace fs = std::filesystem;

nlohmann::json ReconstructionEvaluation::ToJson() const {
  return {{"compensated", compensated.ToJson()}, {"uncompensated", uncompensated.ToJson()}};
}

std::map<int, Rigid3d> PosesByFrame(const fs::path& tum, const fs::path& frames_csv) {
  const auto frames = ReadFramesCsv(frames_csv);
  const auto poses = ReadTum(tum);  // by increasing time
  UWS_CHECK(!frames.empty(), frames_csv.string(), ": no frames");
  const double interval = frames.size() > 1 ? MeanFrameInterval(frames) : 1.0;
  // Each frame takes the pose nearest its time. A trajectory denser than
  // the frames (144 Hz truth against every 5th frame) has several within
  // half an interval of each frame; any but the nearest is another time's.
  std::map<int, Rigid3d> by_frame;
  for (const FrameRecord& frame : frames) {
    const StampedPose* nearest = NearestInTime(poses, frame.timestamp_s, 0.5 * interval + 1e-9);
    if (nearest != nullptr) by_frame[frame.index] = nearest->world_from_camera;
  }
  return by_frame;
}

double MedianViewedDepth(const fs::path& dataset) {
  if (!fs::exists(dataset / "scene.yaml")) return 0.0;
  sim::Scenario scenario = sim::LoadDatasetScenario(dataset);
  scenario.config.scene.Prepare();
  std::vector<double> depths;
  for (const StampedPose& pose : ReadTum(dataset / "groundtruth.tum")) {
    // The optical axis taken straight: a flat port facing the camera, as
    // the simulator's, does not bend it.
    const Rigid3d& world_from_camera = pose.world_from_camera;
    const auto hit = scenario.config.scene.Intersect(
        world_from_camera.translation, world_from_camera.rotation * Eigen::Vector3d::UnitZ());
    if (hit) depths.push_back((hit->point_world - world_from_camera.translation).norm());
  }
  return Median(depths);  // 0 if the axis never met the scene
}

ReconstructionEvaluation EvaluateReconstruction(const fs::path& dataset, const fs::path& result) {
  UWS_CHECK(fs::exists(dataset / "scene.yaml"), (dataset / "scene.yaml").string(),
            ": missing: evaluation needs a simulated dataset with its scene");
  UWS_CHECK(fs::exists(dataset / "groundtruth.tum"), (dataset / "groundtruth.tum").string(),
            ": missing: evaluation needs the true trajectory");
  sim::Scenario scenario = sim::LoadDatasetScenario(dataset);
  scenario.config.scene.Prepare();
  const Camera& camera = scenario.config.rig.cameras.front();
  auto truth = PosesByFrame(dataset / "groundtruth.tum", dataset / "frames.csv");
  auto estimated = PosesByFrame(result / "trajectory.tum", dataset / "frames.csv");
  UWS_CHECK(!estimated.empty(), (result / "trajectory.tum").string(), ": no pose matches a frame");
  // The uncompensated cloud places every profile with the first pose.
  const Rigid3d first_pose = estimated.begin()->second;
  std::map<int, Rigid3d> first_everywhere;
  for (const auto& [frame, pose] : truth) first_everywhere[frame] = first_pose;
  // Further cameras of the rig (DATASET/NAME/, reconstructed into
  // OUT/trajectory_NAME.tum): their frames, true and placed poses.
  const Rig& rig = scenario.config.rig;
  std::map<int, const Camera*> frame_cameras;
  for (size_t c = 1; c < rig.cameras.size(); ++c) {
    const Camera& other = rig.cameras[c];
    const fs::path folder = dataset / other.name,
                   placed = result / ("trajectory_" + other.name + ".tum");
    if (!fs::exists(folder / "frames.csv") || !fs::exists(placed)) continue;
    const Rigid3d main_from_other = rig.CameraFromCamera(0, c);
    for (const auto& [frame, pose] :
         PosesByFrame(folder / "groundtruth.tum", folder / "frames.csv")) {
      truth[frame] = pose;
      first_everywhere[frame] = first_pose * main_from_other;
      frame_cameras[frame] = &other;
    }
    for (const auto& [frame, pose] : PosesByFrame(placed, folder / "frames.csv")) {
      estimated[frame] = pose;
    }
  }
  ReconstructionEvaluation evaluation;
  evaluation.compensated =
      EvaluateCloud(ReadPly(result / "cloud.ply", /*need_frame=*/true), estimated, truth, camera,
                    scenario.config.scene, frame_cameras);
  evaluation.uncompensated =
      EvaluateCloud(ReadPly(result / "cloud_uncompensated.ply", /*need_frame=*/true),
                    first_everywhere, truth, camera, scenario.config.scene, frame_cameras);
  return evaluation;
}

}  // namespace uwscan
