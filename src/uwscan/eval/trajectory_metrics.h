// Trajectory accuracy (thesis §6.3): absolute trajectory error after Sim(3)
// alignment (ATE), relative pose error (RPE, per frame step) and KITTI-style
// drift (translation % and rotation deg/m over fixed path lengths, Geiger et
// al. 2012). Monocular VO is up to scale, so every metric is computed on the
// estimate mapped by the Sim(3) that best aligns its positions.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "uwscan/geometry/sim3_alignment.h"
#include "uwscan/io/tum_trajectory.h"

namespace uwscan {

struct TrajectoryMetricsOptions {
  double max_time_difference_s = 1e-3;  // timestamp association tolerance
  bool align_scale = true;              // Sim(3); false: SE(3)
  // RPE between ground-truth frames i and i + step; 0: the estimate's own
  // step, the most common one between its consecutive poses (1 for an
  // estimate of every frame, 5 for every 5th frame of the ground truth's).
  int rpe_step = 0;
  // RPE only over pairs inside [rpe_from_s, rpe_to_s] (e.g. the hover part
  // of a sequence); the alignment still uses every pose.
  double rpe_from_s = -1e300, rpe_to_s = 1e300;
  // KITTI path lengths (m); empty = 10%, 20%, ..., 50% of the ground-truth path.
  std::vector<double> drift_lengths_m;
  int drift_start_step = 1;  // every k-th frame starts a drift segment (KITTI: 10)
  // Motion magnitudes between ground-truth frames this far apart (0: a
  // tenth of the associated poses).
  int motion_lag = 0;
  // Distance from the camera to the scene along its optical axis (m; 0:
  // unknown). When set, the metrics also tell the camera's motion from the
  // motion of what it looks at (viewed_motion_ratio below).
  double viewed_depth_m = 0.0;
  void Check() const;
};

struct TrajectoryMetrics {
  int associated = 0;        // pose pairs used
  double path_length_m = 0;  // ground-truth path length over the associated poses
  Sim3d alignment;           // ground_truth_world_from_estimate_world
  // A platform that stands still (a static scan: the ground truth's
  // positions all within kStillM of its first) leaves no motion to align:
  // the estimate is then aligned through its first associated pose, scale
  // 1, and the ATE says how far it wandered from where it started.
  static constexpr double kStillM = 1e-6;
  bool aligned_by_first_pose = false;
  // 95 % interval of the Sim(3) scale by a block bootstrap over time (20
  // blocks of consecutive poses, 200 resamples): how well the positions
  // pin the scale down. Narrow on a transect; on a hover whose positions
  // span a few centimetres, millimetres of error move it by percents.
  double scale_interval_low = 1.0, scale_interval_high = 1.0;
  // ATE on positions after alignment (m).
  double ate_rmse_m = 0, ate_mean_m = 0, ate_median_m = 0, ate_max_m = 0;
  // RPE per `rpe_step` ground-truth frames (m, deg), after applying the
  // alignment scale.
  int rpe_step = 1;
  double rpe_trans_rmse_m = 0, rpe_rot_rmse_deg = 0;
  double rpe_trans_mean_m = 0, rpe_rot_mean_deg = 0;
  int rpe_pairs = 0;
  // KITTI drift averaged over all segments of all lengths (none on a path
  // shorter than every length: 0, null in JSON).
  double drift_trans_percent = 0, drift_rot_deg_per_m = 0;
  int drift_segments = 0;
  std::vector<double> drift_lengths_m;
  // Without any alignment (lengths and angles do not depend on the world
  // frame): least-squares ratio, estimated over true, of the translation
  // lengths |t_j - t_i| and of the rotation angles between poses
  // `motion_lag` ground-truth frames apart. A scale error shows in the
  // first alone; the hover's rotation-about-the-scene mode moves them in
  // opposite directions; a focal-length error moves both alike.
  // Not measured (1, null in JSON) where the truth neither moves nor turns
  // over such pairs.
  int motion_lag = 0;
  double motion_translation_ratio = 1.0, motion_rotation_ratio = 1.0;
  bool motion_translation_measured = false, motion_rotation_measured = false;
  // With options.viewed_depth_m (else 0 / 1): over the same pairs, the
  // least-squares ratio, estimated over true, of how far the point
  // viewed_depth_m ahead of the camera on its optical axis moved; and the
  // share of the camera's relative translation error (squared, in the
  // first camera's frame) that its rotation error explains as a turn about
  // that point, t_error = -rotation_error x (0, 0, depth). Through a narrow
  // field over a near-planar scene such a turn hardly changes the image or
  // where the laser's profiles land (the bas-relief ambiguity): a share
  // near 1 says the trajectory's error is of that kind.
  double viewed_depth_m = 0.0;
  double viewed_motion_ratio = 1.0;
  double turn_about_scene_share = 0.0;
  // Every figure above, in metres and degrees (`uwscan evaluate --json`);
  // the viewed-point figures only when computed.
  nlohmann::json ToJson() const;
};

// Associates `estimate` with `ground_truth` by timestamp and computes the
// metrics. Throws uwscan::Error when fewer than 3 poses associate, or when
// the positions cannot be aligned and the ground truth moves.
TrajectoryMetrics ComputeTrajectoryMetrics(const std::vector<StampedPose>& estimate,
                                           const std::vector<StampedPose>& ground_truth,
                                           const TrajectoryMetricsOptions& options = {});

// Human-readable report (several lines) for the CLI.
std::string FormatTrajectoryMetrics(const TrajectoryMetrics& metrics);

}  // namespace uwscan
