#include "uwscan/calib/detection_benchmark.h"

#include <cmath>
#include <cstdio>
#include <random>

namespace uwscan {

std::vector<DetectionCondition> StandardDetectionConditions() {
  std::vector<DetectionCondition> conditions;
  auto add = [&](const std::string& name, double blur, double noise, double contrast) {
    DetectionCondition c;
    c.name = name;
    c.render.blur_sigma_px = blur;
    c.render.noise_sigma = noise;
    c.render.contrast = contrast;
    c.render.width = 640;  // VGA keeps the exhaustive SB search affordable
    c.render.height = 480;
    c.render.focal_px = 600.0;
    conditions.push_back(c);
  };
  add("clear", 0.5, 1.0, 1.0);
  add("steep 40-50 deg", 0.5, 1.0, 1.0);
  conditions.back().min_tilt_rad = 40.0 * M_PI / 180.0;
  conditions.back().max_tilt_rad = 50.0 * M_PI / 180.0;
  add("blur 1 px", 1.0, 1.0, 1.0);
  add("blur 2 px", 2.0, 1.0, 1.0);
  add("blur 3 px", 3.0, 1.0, 1.0);
  add("noise 5", 0.5, 5.0, 1.0);
  add("noise 10", 0.5, 10.0, 1.0);
  add("noise 20", 0.5, 20.0, 1.0);
  add("turbid c=0.30", 1.5, 3.0, 0.30);
  add("turbid c=0.15", 1.5, 3.0, 0.15);
  add("turbid c=0.08", 1.5, 3.0, 0.08);
  return conditions;
}

std::vector<DetectionBenchmarkRow> RunDetectionBenchmark(
    const BoardSpec& board, const std::vector<DetectionCondition>& conditions, int trials,
    unsigned seed) {
  std::vector<DetectionBenchmarkRow> rows;
  DetectionOptions gates_off;
  gates_off.max_edge_width_px = 1e9;
  gates_off.min_contrast = 0.0;
  for (const DetectionCondition& condition : conditions) {
    for (CornerDetector detector : {CornerDetector::kSectorBased,
                                    CornerDetector::kSectorBasedSubPix, CornerDetector::kClassic}) {
      DetectionBenchmarkRow row;
      row.condition = condition.name;
      row.detector = detector == CornerDetector::kSectorBased ? "findChessboardCornersSB"
                     : detector == CornerDetector::kClassic
                         ? "findChessboardCorners + cornerSubPix 11x11"
                         : "findChessboardCornersSB + cornerSubPix 11x11";
      row.trials = trials;
      gates_off.detector = detector;
      std::mt19937 rng(seed);
      std::uniform_real_distribution<double> uniform(-1.0, 1.0);
      double sum_sq = 0.0;
      int count = 0;
      for (int t = 0; t < trials; ++t) {
        BoardRenderOptions render = condition.render;
        render.seed = seed + t;
        const Eigen::Vector3d centre((board.cols - 1) * board.square_m / 2,
                                     (board.rows - 1) * board.square_m / 2, 0);
        const double tilt =
            condition.min_tilt_rad +
            (condition.max_tilt_rad - condition.min_tilt_rad) * 0.5 * (1.0 + uniform(rng));
        const double axis = M_PI * uniform(rng);
        const Eigen::Quaterniond rotation(
            Eigen::AngleAxisd(tilt, Eigen::Vector3d(std::cos(axis), std::sin(axis), 0.0)) *
            Eigen::AngleAxisd(0.3 * uniform(rng), Eigen::Vector3d::UnitZ()));
        const double range = board.cols * board.square_m * (1.3 + 0.4 * uniform(rng));
        const Eigen::Vector3d position(0.1 * range * uniform(rng), 0.1 * range * uniform(rng),
                                       range);
        const Rigid3d pose(rotation, position - rotation * centre);
        std::vector<Eigen::Vector2d> truth;
        const cv::Mat image = RenderBoard(board, pose, render, &truth);
        bool inside = true;
        for (const Eigen::Vector2d& c : truth) {
          inside &=
              c.x() > 10 && c.y() > 10 && c.x() < render.width - 11 && c.y() < render.height - 11;
        }
        if (!inside) {  // draw another pose: only whole boards count
          --t;
          continue;
        }
        const BoardDetection detection = DetectBoard(image, board, gates_off);
        if (!detection.found) continue;
        // Detectors may start at either end of the board: match both orders.
        double forward = 0.0, backward = 0.0;
        const size_t n = truth.size();
        for (size_t i = 0; i < n; ++i) {
          forward += (detection.points[i] - truth[i]).squaredNorm();
          backward += (detection.points[i] - truth[n - 1 - i]).squaredNorm();
        }
        const bool reversed = backward < forward;
        ++row.detected;
        for (size_t i = 0; i < n; ++i) {
          const double e = (detection.points[i] - truth[reversed ? n - 1 - i : i]).norm();
          sum_sq += e * e;
          row.max_error_px = std::max(row.max_error_px, e);
          ++count;
        }
      }
      row.rms_error_px = count ? std::sqrt(sum_sq / count) : NAN;
      rows.push_back(row);
    }
  }
  return rows;
}

std::string DetectionBenchmarkMarkdown(const std::vector<DetectionBenchmarkRow>& rows) {
  std::string out =
      "| condition | detector | detected | corner RMS error (px) | max error (px) |\n"
      "|---|---|---|---|---|\n";
  char line[256];
  for (const auto& row : rows) {
    std::snprintf(line, sizeof(line), "| %s | %s | %d/%d | %.3f | %.3f |\n", row.condition.c_str(),
                  row.detector.c_str(), row.detected, row.trials, row.rms_error_px,
                  row.max_error_px);
    out += line;
  }
  return out;
}

}  // namespace uwscan
