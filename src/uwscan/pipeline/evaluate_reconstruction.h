// Evaluation of a `uwscan reconstruct` result against a simulated dataset's
// ground truth: the compensated and the uncompensated cloud (thesis §6.4:
// plane standard deviation and distance errors on the target; §6.5:
// cylinder fit on the shaft).
#pragma once

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>

#include "uwscan/eval/cloud_metrics.h"

namespace uwscan {

struct ReconstructionEvaluation {
  CloudAccuracy compensated;
  CloudAccuracy uncompensated;
  nlohmann::json ToJson() const;
};

// Frame index of each pose of a TUM trajectory, matched to frames.csv
// timestamps: each frame takes the pose nearest its time, if within half
// the frames' mean interval.
std::map<int, Rigid3d> PosesByFrame(const std::filesystem::path& tum,
                                    const std::filesystem::path& frames_csv);

// The median distance from the camera to the scene along its optical axis
// over the true trajectory (m), for TrajectoryMetricsOptions::viewed_depth_m;
// 0 when the dataset has no scene.yaml (not simulated) or the axis never
// meets the scene.
double MedianViewedDepth(const std::filesystem::path& dataset);

ReconstructionEvaluation EvaluateReconstruction(const std::filesystem::path& dataset,
                                                const std::filesystem::path& result);

}  // namespace uwscan
