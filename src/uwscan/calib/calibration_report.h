// Calibration reports: JSON (nlohmann) and a PNG of the residual field over
// the image, written atomically (issue 5, item 5).
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "uwscan/calib/camera_calibration.h"
#include "uwscan/calib/checkerboard.h"
#include "uwscan/calib/laser_calibration.h"
#include "uwscan/util/atomic_file.h"

namespace uwscan {

nlohmann::json DetectionsToJson(const std::vector<BoardDetection>& detections);
// Stage, camera, parameters with standard deviations, per-view RMS and
// which views were dropped and why.
nlohmann::json CameraResultToJson(const CameraCalibrationResult& result);
nlohmann::json LaserResultToJson(const LaserCalibrationResult& result);

// Pinhole vs flat port at several ranges: the best pinhole for the flat-port
// camera fitted at `fit_depth_m`, and optionally a pinhole calibrated on the
// same images, compared with the flat-port model on planes at each range.
nlohmann::json PinholeComparisonJson(const Camera& flatport, const Camera* calibrated_pinhole,
                                     const std::vector<double>& ranges_m, double fit_depth_m);

// Residual vectors drawn at the measured corners, scaled so that the 95th
// percentile is 40 px long, coloured by magnitude, with a legend.
cv::Mat DrawResidualField(const CameraCalibrationResult& result, int width, int height);

// DIR/<stem>.json and DIR/<stem>_residuals.png (with a plot), added to
// `files` (renamed into place by their Commit(), with the rig's).
void AddReportFiles(const std::filesystem::path& dir, const std::string& stem,
                    const nlohmann::json& report, const cv::Mat* plot, StagedFiles* files);

}  // namespace uwscan
