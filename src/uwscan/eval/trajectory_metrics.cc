#include "uwscan/eval/trajectory_metrics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <utility>

#include "uwscan/util/error.h"
#include "uwscan/util/json.h"

namespace uwscan {
namespace {

// See TrajectoryMetrics::scale_interval_low. Blocks of consecutive poses
// keep the errors' correlation in time; deterministic (fixed seed).
std::pair<double, double> ScaleInterval(const std::vector<Eigen::Vector3d>& estimate,
                                        const std::vector<Eigen::Vector3d>& truth) {
  constexpr int kBlocks = 20, kResamples = 200;
  const size_t n = estimate.size();
  const size_t block = std::max<size_t>(1, (n + kBlocks - 1) / kBlocks);
  const size_t blocks = (n + block - 1) / block;
  std::mt19937 rng(12345);
  std::uniform_int_distribution<size_t> pick(0, blocks - 1);
  std::vector<double> scales;
  std::vector<Eigen::Vector3d> source, target;
  for (int r = 0; r < kResamples; ++r) {
    source.clear(), target.clear();
    for (size_t b = 0; b < blocks; ++b) {
      const size_t first = pick(rng) * block;
      for (size_t i = first; i < std::min(n, first + block); ++i) {
        source.push_back(estimate[i]);
        target.push_back(truth[i]);
      }
    }
    if (const auto sim = AlignSim3(source, target, true)) scales.push_back(sim->scale);
  }
  if (scales.size() < 20) return {std::nan(""), std::nan("")};
  std::sort(scales.begin(), scales.end());
  return {scales[scales.size() * 25 / 1000], scales[scales.size() * 975 / 1000]};
}

double AngleDeg(const Eigen::Quaterniond& q) {
  return Eigen::AngleAxisd(q.normalized()).angle() * 180.0 / M_PI;
}

// Relative motion of the estimate vs ground truth between frames i and j:
// E = (gt_i^-1 gt_j)^-1 (est_i^-1 est_j), the estimate already aligned.
Rigid3d RelativeError(const Rigid3d& gt_i, const Rigid3d& gt_j, const Rigid3d& est_i,
                      const Rigid3d& est_j) {
  return (gt_i.Inverse() * gt_j).Inverse() * (est_i.Inverse() * est_j);
}

// The most common step between consecutive ground-truth indices (the
// smaller on a tie; 1 for fewer than two).
int MostCommonStep(const std::vector<long>& gt_index) {
  std::map<long, int> counts;
  for (size_t i = 1; i < gt_index.size(); ++i) ++counts[gt_index[i] - gt_index[i - 1]];
  long step = 1;
  int most = 0;
  for (const auto& [candidate, count] : counts) {
    if (count > most && candidate >= 1) step = candidate, most = count;
  }
  return int(step);
}

}  // namespace

void TrajectoryMetricsOptions::Check() const {
  UWS_CHECK(max_time_difference_s >= 0, "max_time_difference_s must be >= 0");
  UWS_CHECK(!std::isnan(rpe_from_s) && !std::isnan(rpe_to_s) && rpe_from_s <= rpe_to_s,
            "the RPE's time range must be a range, got ", rpe_from_s, " to ", rpe_to_s);
  UWS_CHECK(rpe_step >= 0, "rpe_step must be >= 0 (0: the estimate's own)");
  UWS_CHECK(drift_start_step >= 1, "drift_start_step must be >= 1");
  UWS_CHECK(motion_lag >= 0, "motion_lag must be >= 0");
  UWS_CHECK(viewed_depth_m >= 0 && std::isfinite(viewed_depth_m),
            "viewed_depth_m must be >= 0, got ", viewed_depth_m);
  for (double length : drift_lengths_m) UWS_CHECK(length > 0, "drift lengths must be > 0");
}

TrajectoryMetrics ComputeTrajectoryMetrics(const std::vector<StampedPose>& estimate,
                                           const std::vector<StampedPose>& ground_truth,
                                           const TrajectoryMetricsOptions& options) {
  options.Check();
  // Associate by nearest timestamp (ground truth sorted by time).
  std::vector<StampedPose> gt_sorted = ground_truth;
  std::sort(gt_sorted.begin(), gt_sorted.end(), [](const StampedPose& a, const StampedPose& b) {
    return a.timestamp_s < b.timestamp_s;
  });
  std::vector<Rigid3d> est, gt;
  std::vector<long> gt_index;  // position in the time-sorted ground truth
  std::vector<double> stamps;
  for (const StampedPose& pose : estimate) {
    const StampedPose* best =
        NearestInTime(gt_sorted, pose.timestamp_s, options.max_time_difference_s);
    if (best == nullptr) continue;
    est.push_back(pose.world_from_camera);
    gt.push_back(best->world_from_camera);
    gt_index.push_back(long(best - gt_sorted.data()));
    stamps.push_back(pose.timestamp_s);
  }
  TrajectoryMetrics metrics;
  metrics.associated = int(est.size());
  if (est.size() < 3) {
    // Both files' time spans; about a thousand times apart, one of the two
    // is in milliseconds.
    const auto span = [](const std::vector<StampedPose>& poses) {
      if (poses.empty()) return std::pair<double, double>(0.0, 0.0);
      const auto [first, last] = std::minmax_element(
          poses.begin(), poses.end(),
          [](const StampedPose& a, const StampedPose& b) { return a.timestamp_s < b.timestamp_s; });
      return std::pair(first->timestamp_s, last->timestamp_s);
    };
    const auto text = [](const std::vector<StampedPose>& poses, std::pair<double, double> times) {
      return poses.empty() ? std::string("none")
                           : internal::Concat(times.first, " to ", times.second, " s");
    };
    const auto est_span = span(estimate), gt_span = span(gt_sorted);
    const double est_duration = est_span.second - est_span.first;
    const double gt_duration = gt_span.second - gt_span.first;
    const auto thousandfold = [](double a, double b) { return a > 500.0 * b && a < 2000.0 * b; };
    UWS_THROW("trajectory metrics: only ", est.size(),
              " poses associate with the ground truth by timestamp (need >= 3; within ",
              options.max_time_difference_s, " s; the estimate's times ", text(estimate, est_span),
              ", the ground truth's ", text(gt_sorted, gt_span),
              thousandfold(est_duration, gt_duration) ? ": the estimate's times in milliseconds?"
              : thousandfold(gt_duration, est_duration)
                  ? ": the ground truth's times in milliseconds?"
                  : "",
              ")");
  }

  std::vector<Eigen::Vector3d> est_positions, gt_positions;
  for (size_t i = 0; i < est.size(); ++i) {
    est_positions.push_back(est[i].translation);
    gt_positions.push_back(gt[i].translation);
  }
  std::optional<Sim3d> alignment = AlignSim3(est_positions, gt_positions, options.align_scale);
  if (!alignment) {
    double farthest = 0.0;
    for (const Eigen::Vector3d& p : gt_positions)
      farthest = std::max(farthest, (p - gt_positions.front()).norm());
    UWS_CHECK(farthest < TrajectoryMetrics::kStillM,
              "trajectory metrics: positions are degenerate (collinear or identical), "
              "cannot align");
    const Rigid3d first = gt.front() * est.front().Inverse();
    alignment = Sim3d{1.0, first.rotation, first.translation};
    metrics.aligned_by_first_pose = true;
  }
  metrics.alignment = *alignment;
  if (options.align_scale && !metrics.aligned_by_first_pose) {
    const auto [low, high] = ScaleInterval(est_positions, gt_positions);
    metrics.scale_interval_low = low, metrics.scale_interval_high = high;
  }
  std::vector<Rigid3d> aligned;
  for (const Rigid3d& pose : est) aligned.push_back(metrics.alignment * pose);

  // ATE.
  std::vector<double> errors;
  double sum = 0, sum_sq = 0;
  for (size_t i = 0; i < est.size(); ++i) {
    const double e = (aligned[i].translation - gt[i].translation).norm();
    errors.push_back(e);
    sum += e;
    sum_sq += e * e;
  }
  const double n = double(errors.size());
  metrics.ate_rmse_m = std::sqrt(sum_sq / n);
  metrics.ate_mean_m = sum / n;
  metrics.ate_max_m = *std::max_element(errors.begin(), errors.end());
  std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
  metrics.ate_median_m = errors[errors.size() / 2];

  // RPE between ground-truth frames `rpe_step` apart (pairs across a
  // tracking gap are skipped).
  metrics.rpe_step = options.rpe_step > 0 ? options.rpe_step : MostCommonStep(gt_index);
  double t_sq = 0, r_sq = 0, t_sum = 0, r_sum = 0;
  for (size_t i = 0; i + 1 < est.size(); ++i) {
    size_t j = i + 1;
    while (j < est.size() && gt_index[j] - gt_index[i] < metrics.rpe_step) ++j;
    if (j >= est.size() || gt_index[j] - gt_index[i] != metrics.rpe_step) continue;
    if (stamps[i] < options.rpe_from_s || stamps[j] > options.rpe_to_s) continue;
    const Rigid3d error = RelativeError(gt[i], gt[j], aligned[i], aligned[j]);
    const double t = error.translation.norm(), r = AngleDeg(error.rotation);
    t_sq += t * t, r_sq += r * r, t_sum += t, r_sum += r;
    ++metrics.rpe_pairs;
  }
  if (metrics.rpe_pairs > 0) {
    metrics.rpe_trans_rmse_m = std::sqrt(t_sq / metrics.rpe_pairs);
    metrics.rpe_rot_rmse_deg = std::sqrt(r_sq / metrics.rpe_pairs);
    metrics.rpe_trans_mean_m = t_sum / metrics.rpe_pairs;
    metrics.rpe_rot_mean_deg = r_sum / metrics.rpe_pairs;
  }

  // Motion magnitudes, estimated over true, without alignment.
  metrics.motion_lag =
      options.motion_lag > 0 ? options.motion_lag : std::max(1, int(est.size()) / 10);
  double t_cross = 0, t_true = 0, r_cross = 0, r_true = 0;
  double v_cross = 0, v_true = 0, error_squared = 0, unexplained_squared = 0;
  const Eigen::Vector3d viewed(0.0, 0.0, options.viewed_depth_m);
  for (size_t i = 0, j = 0; i < est.size(); ++i) {
    j = std::max(j, i + 1);
    while (j < est.size() && gt_index[j] - gt_index[i] < metrics.motion_lag) ++j;
    if (j >= est.size()) break;
    if (gt_index[j] - gt_index[i] != metrics.motion_lag) continue;
    const double t_est = (est[j].translation - est[i].translation).norm();
    const double t_gt = (gt[j].translation - gt[i].translation).norm();
    const double r_est = est[i].rotation.angularDistance(est[j].rotation);
    const double r_gt = gt[i].rotation.angularDistance(gt[j].rotation);
    t_cross += t_est * t_gt, t_true += t_gt * t_gt;
    r_cross += r_est * r_gt, r_true += r_gt * r_gt;
    if (options.viewed_depth_m > 0) {
      const double v_est = ((est[j] * viewed) - (est[i] * viewed)).norm();
      const double v_gt = ((gt[j] * viewed) - (gt[i] * viewed)).norm();
      v_cross += v_est * v_gt, v_true += v_gt * v_gt;
      // Relative motions in camera i's frame (no alignment needed).
      const Rigid3d rel_est = est[i].Inverse() * est[j];
      const Rigid3d rel_gt = gt[i].Inverse() * gt[j];
      const Eigen::Vector3d t_error = rel_est.translation - rel_gt.translation;
      // The rotation error in camera i's frame, rel_est = error * rel_gt.
      const Eigen::AngleAxisd error(rel_est.rotation * rel_gt.rotation.conjugate());
      const Eigen::Vector3d w_error = error.angle() * error.axis();
      error_squared += t_error.squaredNorm();
      unexplained_squared += (t_error + w_error.cross(viewed)).squaredNorm();
    }
  }
  metrics.motion_translation_measured = t_true > 0;
  metrics.motion_rotation_measured = r_true > 0;
  metrics.motion_translation_ratio = t_true > 0 ? t_cross / t_true : 1.0;
  metrics.motion_rotation_ratio = r_true > 0 ? r_cross / r_true : 1.0;
  if (options.viewed_depth_m > 0 && v_true > 0) {
    metrics.viewed_depth_m = options.viewed_depth_m;
    metrics.viewed_motion_ratio = v_cross / v_true;
    metrics.turn_about_scene_share =
        error_squared > 0 ? std::max(0.0, 1.0 - unexplained_squared / error_squared) : 0.0;
  }

  // KITTI drift: cumulative ground-truth distance, then for every start
  // frame and length the first frame at least that far along the path.
  std::vector<double> distance(gt.size(), 0.0);
  for (size_t i = 1; i < gt.size(); ++i) {
    distance[i] = distance[i - 1] + (gt[i].translation - gt[i - 1].translation).norm();
  }
  metrics.path_length_m = distance.back();
  metrics.drift_lengths_m = options.drift_lengths_m;
  if (metrics.drift_lengths_m.empty()) {
    for (int k = 1; k <= 5; ++k) metrics.drift_lengths_m.push_back(0.1 * k * distance.back());
  }
  double t_drift = 0, r_drift = 0;
  for (size_t first = 0; first < gt.size(); first += options.drift_start_step) {
    for (double length : metrics.drift_lengths_m) {
      if (!(length > 0)) continue;
      const auto last_it =
          std::lower_bound(distance.begin() + first, distance.end(), distance[first] + length);
      if (last_it == distance.end()) continue;
      const size_t last = size_t(last_it - distance.begin());
      const Rigid3d error = RelativeError(gt[first], gt[last], aligned[first], aligned[last]);
      t_drift += error.translation.norm() / length;
      r_drift += AngleDeg(error.rotation) / length;
      ++metrics.drift_segments;
    }
  }
  if (metrics.drift_segments > 0) {
    metrics.drift_trans_percent = 100.0 * t_drift / metrics.drift_segments;
    metrics.drift_rot_deg_per_m = r_drift / metrics.drift_segments;
  }
  return metrics;
}

nlohmann::json TrajectoryMetrics::ToJson() const {
  const bool drift = drift_segments > 0;
  nlohmann::json json = {
      {"associated", associated},
      {"path_length_m", path_length_m},
      {"sim3",
       {{"scale", alignment.scale},
        {"scale_interval_95", aligned_by_first_pose
                                  ? nlohmann::json()
                                  : nlohmann::json({scale_interval_low, scale_interval_high})},
        {"aligned_by_first_pose", aligned_by_first_pose},
        {"rotation_wxyz",
         {alignment.rotation.w(), alignment.rotation.x(), alignment.rotation.y(),
          alignment.rotation.z()}},
        {"translation_m",
         {alignment.translation.x(), alignment.translation.y(), alignment.translation.z()}}}},
      {"ate_m",
       {{"rmse", ate_rmse_m}, {"mean", ate_mean_m}, {"median", ate_median_m}, {"max", ate_max_m}}},
      {"rpe",
       {{"step", rpe_step},
        {"pairs", rpe_pairs},
        {"translation_rmse_m", ValueOrNull(rpe_pairs > 0, rpe_trans_rmse_m)},
        {"rotation_rmse_deg", ValueOrNull(rpe_pairs > 0, rpe_rot_rmse_deg)},
        {"translation_mean_m", ValueOrNull(rpe_pairs > 0, rpe_trans_mean_m)},
        {"rotation_mean_deg", ValueOrNull(rpe_pairs > 0, rpe_rot_mean_deg)}}},
      {"drift",
       {{"segments", drift_segments},
        {"translation_percent", ValueOrNull(drift, drift_trans_percent)},
        {"rotation_deg_per_m", ValueOrNull(drift, drift_rot_deg_per_m)},
        {"lengths_m", drift_lengths_m}}},
      {"motion",
       {{"lag_frames", motion_lag},
        {"translation_ratio", ValueOrNull(motion_translation_measured, motion_translation_ratio)},
        {"rotation_ratio", ValueOrNull(motion_rotation_measured, motion_rotation_ratio)}}}};
  if (viewed_depth_m > 0) {
    json["motion"]["viewed_depth_m"] = viewed_depth_m;
    json["motion"]["viewed_point_ratio"] = viewed_motion_ratio;
    json["motion"]["turn_about_scene_share"] = turn_about_scene_share;
  }
  return json;
}

std::string FormatTrajectoryMetrics(const TrajectoryMetrics& m) {
  char buffer[1024];
  std::string out;
  if (m.aligned_by_first_pose) {
    std::snprintf(buffer, sizeof(buffer),
                  "poses: %d associated, ground-truth path %.3f m: the platform stands still, "
                  "so the estimate is aligned through its first pose (no scale)\n",
                  m.associated, m.path_length_m);
  } else {
    std::snprintf(buffer, sizeof(buffer),
                  "poses: %d associated, ground-truth path %.3f m, Sim(3) scale %.6g "
                  "(95 %% block-bootstrap interval %.4g-%.4g)\n",
                  m.associated, m.path_length_m, m.alignment.scale, m.scale_interval_low,
                  m.scale_interval_high);
  }
  out += buffer;
  std::snprintf(buffer, sizeof(buffer),
                "ATE (after alignment): rmse %.4f m, mean %.4f m, median %.4f m, max %.4f m\n",
                m.ate_rmse_m, m.ate_mean_m, m.ate_median_m, m.ate_max_m);
  out += buffer;
  const std::string per =
      m.rpe_step == 1 ? "RPE per frame" : "RPE per " + std::to_string(m.rpe_step) + " frames";
  if (m.rpe_pairs > 0) {
    std::snprintf(buffer, sizeof(buffer), "%s: %.3f mm, %.3f mdeg (rmse over %d pairs)\n",
                  per.c_str(), 1e3 * m.rpe_trans_rmse_m, 1e3 * m.rpe_rot_rmse_deg, m.rpe_pairs);
  } else {
    std::snprintf(buffer, sizeof(buffer),
                  "%s: no pair of poses the step apart within the time range\n", per.c_str());
  }
  out += buffer;
  if (m.drift_segments > 0) {
    std::snprintf(buffer, sizeof(buffer),
                  "drift (KITTI, %d segments): %.3f %% translation, %.4f deg/m rotation\n",
                  m.drift_segments, m.drift_trans_percent, m.drift_rot_deg_per_m);
  } else {
    std::snprintf(buffer, sizeof(buffer),
                  "drift (KITTI): no segment (the path is shorter than every length)\n");
  }
  out += buffer;
  const auto ratio = [](bool measured, double value, const char* unmeasured) {
    if (!measured) return std::string("- (the truth does not ") + unmeasured + ")";
    char text[32];
    std::snprintf(text, sizeof(text), "%.4f", value);
    return std::string(text);
  };
  std::snprintf(buffer, sizeof(buffer),
                "motion over %d frames, estimated / true (no alignment): translation %s, "
                "rotation %s\n",
                m.motion_lag,
                ratio(m.motion_translation_measured, m.motion_translation_ratio, "move").c_str(),
                ratio(m.motion_rotation_measured, m.motion_rotation_ratio, "turn").c_str());
  out += buffer;
  if (m.viewed_depth_m > 0) {
    std::snprintf(buffer, sizeof(buffer),
                  "the point %.3f m ahead on the optical axis (the scene): moved %.4f of the "
                  "truth; %.0f %% of the camera's translation error is a turn about it\n",
                  m.viewed_depth_m, m.viewed_motion_ratio, 100.0 * m.turn_about_scene_share);
    out += buffer;
  }
  out += "drift lengths (m):";
  for (double length : m.drift_lengths_m) {
    std::snprintf(buffer, sizeof(buffer), " %.3g", length);
    out += buffer;
  }
  return out + "\n";
}

}  // namespace uwscan
