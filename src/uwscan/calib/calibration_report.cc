#include "uwscan/calib/calibration_report.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "uwscan/eval/port_analysis.h"
#include "uwscan/util/atomic_file.h"
#include "uwscan/util/error.h"

namespace uwscan {
namespace {

nlohmann::json Finite(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

nlohmann::json CameraToJson(const Camera& camera) {
  nlohmann::json j;
  j["name"] = camera.name;
  j["model"] = CameraModelName(camera.model);
  j["width"] = camera.width;
  j["height"] = camera.height;
  j["intrinsics"] = camera.intrinsics;
  j["distortion"] = camera.distortion;
  if (camera.IsFlatPort()) {
    j["port"] = {
        {"normal", {camera.port.normal.x(), camera.port.normal.y(), camera.port.normal.z()}},
        {"tilt_deg", camera.port.TiltRad() * 180.0 / M_PI},
        {"d_air", camera.port.d_air},
        {"d_glass", camera.port.d_glass},
        {"n_air", camera.port.n_air},
        {"n_glass", camera.port.n_glass},
        {"n_water", camera.port.n_water}};
  }
  return j;
}

}  // namespace

nlohmann::json DetectionsToJson(const std::vector<BoardDetection>& detections) {
  nlohmann::json list = nlohmann::json::array();
  for (const BoardDetection& d : detections) {
    list.push_back({{"image", d.name},
                    {"found", d.found},
                    {"reason", d.reason},
                    {"corners", d.corners},
                    {"edge_width_px", Finite(d.edge_width_px)},
                    {"contrast", Finite(d.contrast)}});
  }
  return list;
}

nlohmann::json CameraResultToJson(const CameraCalibrationResult& result) {
  nlohmann::json j;
  j["stage"] = result.stage;
  j["camera"] = CameraToJson(result.camera);
  j["rms_px"] = result.rms_px;
  j["used_views"] = result.used_views;
  j["iterations"] = result.iterations;
  j["outlier_rounds"] = result.outlier_rounds;
  j["converged"] = result.converged;
  if (result.opencv_rms_px >= 0) j["opencv_calibrate_camera_rms_px"] = result.opencv_rms_px;
  nlohmann::json parameters = nlohmann::json::array();
  for (const ParameterEstimate& p : result.parameters) {
    parameters.push_back({{"name", p.name}, {"value", p.value}, {"std", Finite(p.std_dev)}});
  }
  j["parameters"] = parameters;
  nlohmann::json views = nlohmann::json::array();
  for (const ViewReport& v : result.views) {
    const Eigen::Vector3d t = v.camera_from_board.translation;
    views.push_back({{"name", v.name},
                     {"used", v.used},
                     {"dropped_reason", v.dropped_reason},
                     {"rms_px", Finite(v.rms_px)},
                     {"range_m", t.norm()}});
  }
  j["views"] = views;
  return j;
}

nlohmann::json LaserResultToJson(const LaserCalibrationResult& result) {
  const Rigid3d& pose = result.laser.camera_from_laser;
  return {
      {"camera_from_laser",
       {{"q", {pose.rotation.w(), pose.rotation.x(), pose.rotation.y(), pose.rotation.z()}},
        {"t", {pose.translation.x(), pose.translation.y(), pose.translation.z()}}}},
      {"p1", result.laser.p1},
      {"plane_normal", {result.plane_normal.x(), result.plane_normal.y(), result.plane_normal.z()}},
      {"plane_d_m", result.plane_d},
      {"points", result.points},
      {"inliers", result.inliers},
      {"plane_rms_mm", result.plane_rms_m * 1e3},
      {"sheet_rms_mm", result.sheet_rms_m * 1e3},
      {"baseline_mm", result.baseline_m * 1e3},
      {"sheet_angle_to_camera_x_deg", result.sheet_angle_deg},
      {"points_per_view", result.view_points}};
}

nlohmann::json PinholeComparisonJson(const Camera& flatport, const Camera* calibrated_pinhole,
                                     const std::vector<double>& ranges_m, double fit_depth_m) {
  PinholeFitOptions options;
  options.depth_m = fit_depth_m;
  options.grid_step_px = 40;
  const PinholeFit fit = FitPinholeToFlatPort(flatport, options);
  nlohmann::json rows = nlohmann::json::array();
  for (double range : ranges_m) {
    const ErrorStats best = PinholeErrorAtDepth(flatport, fit.pinhole, range, 40);
    nlohmann::json row = {{"range_m", range},
                          {"best_pinhole_median_px", best.median_px},
                          {"best_pinhole_max_px", best.max_px}};
    if (calibrated_pinhole) {
      const ErrorStats calibrated = PinholeErrorAtDepth(flatport, *calibrated_pinhole, range, 40);
      row["calibrated_pinhole_median_px"] = calibrated.median_px;
      row["calibrated_pinhole_max_px"] = calibrated.max_px;
    }
    rows.push_back(row);
  }
  return {{"fit_depth_m", fit_depth_m}, {"ranges", rows}};
}

cv::Mat DrawResidualField(const CameraCalibrationResult& result, int width, int height) {
  const double scale_image = std::min(1.0, 1280.0 / std::max(width, 1));
  const int w = std::max(64, static_cast<int>(width * scale_image));
  const int h = std::max(64, static_cast<int>(height * scale_image));
  cv::Mat plot(h + 60, w, CV_8UC3, cv::Scalar(255, 255, 255));
  std::vector<double> magnitudes;
  for (const CornerResidual& r : result.residuals) magnitudes.push_back(std::hypot(r.du, r.dv));
  double p95 = 0.0;
  if (!magnitudes.empty()) {
    std::vector<double> sorted = magnitudes;
    std::sort(sorted.begin(), sorted.end());
    p95 = sorted[std::min(sorted.size() - 1, static_cast<size_t>(0.95 * sorted.size()))];
  }
  const double arrow_scale = p95 > 0 ? 40.0 / p95 : 1.0;
  cv::Mat area = plot(cv::Rect(0, 0, w, h));  // clips the arrows to the image
  cv::rectangle(plot, cv::Rect(0, 0, w, h), cv::Scalar(180, 180, 180));
  for (size_t i = 0; i < result.residuals.size(); ++i) {
    const CornerResidual& r = result.residuals[i];
    const cv::Point2d from(r.u * scale_image, r.v * scale_image);
    const cv::Point2d to = from + cv::Point2d(r.du, r.dv) * arrow_scale;
    const double t = p95 > 0 ? std::min(1.0, magnitudes[i] / (2 * p95)) : 0.0;
    const cv::Scalar colour(255 * (1 - t), 60, 255 * t);  // blue small -> red large
    cv::line(area, from, to, colour, 1, cv::LINE_AA);
    cv::circle(area, from, 1, cv::Scalar(0, 0, 0), cv::FILLED);
  }
  // Mean residual per cell of an 8 x 6 grid: systematic patterns (an
  // unmodelled port, a wrong distortion) show as coherent thick arrows.
  const int cells_x = 8, cells_y = 6;
  std::vector<Eigen::Vector3d> cells(cells_x * cells_y, Eigen::Vector3d::Zero());
  for (const CornerResidual& r : result.residuals) {
    const int cx = std::clamp(static_cast<int>(r.u / width * cells_x), 0, cells_x - 1);
    const int cy = std::clamp(static_cast<int>(r.v / height * cells_y), 0, cells_y - 1);
    cells[cy * cells_x + cx] += Eigen::Vector3d(r.du, r.dv, 1.0);
  }
  for (int cy = 0; cy < cells_y; ++cy) {
    for (int cx = 0; cx < cells_x; ++cx) {
      const Eigen::Vector3d& c = cells[cy * cells_x + cx];
      if (c.z() < 3) continue;
      const cv::Point2d centre((cx + 0.5) * w / cells_x, (cy + 0.5) * h / cells_y);
      const cv::Point2d mean(c.x() / c.z(), c.y() / c.z());
      cv::arrowedLine(area, centre, centre + mean * arrow_scale * 3.0, cv::Scalar(0, 0, 0), 2,
                      cv::LINE_AA, 0, 0.2);
    }
  }
  char text[256];
  std::snprintf(
      text, sizeof(text),
      "%s: residuals x%.0f (40 px = %.3f px, p95); black: cell means x%.0f; RMS %.3f px, %d views",
      result.stage.c_str(), arrow_scale, p95, 3.0 * arrow_scale, result.rms_px, result.used_views);
  cv::putText(plot, text, cv::Point(8, h + 25), cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar(0, 0, 0),
              1, cv::LINE_AA);
  return plot;
}

void AddReportFiles(const std::filesystem::path& dir, const std::string& stem,
                    const nlohmann::json& report, const cv::Mat* plot, StagedFiles* files) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  UWS_CHECK(!ec && std::filesystem::is_directory(dir), dir.string(),
            ": cannot create the report directory");
  files->Add(dir / (stem + ".json"), report.dump(2) + "\n");
  if (plot) {
    std::vector<uchar> png;
    UWS_CHECK(cv::imencode(".png", *plot, png), "cannot encode the residual plot");
    files->Add(dir / (stem + "_residuals.png"), std::string(png.begin(), png.end()),
               /*binary=*/true);
  }
}

}  // namespace uwscan
