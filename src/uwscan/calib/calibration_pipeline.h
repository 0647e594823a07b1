// Controllers behind `uwscan calibrate camera|laser`: image folders in, a
// calibrated camera or laser and a report out. The CLI only parses options,
// prints and writes files.
#pragma once

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <optional>
#include <string>

#include "uwscan/calib/camera_calibration.h"
#include "uwscan/calib/checkerboard.h"
#include "uwscan/calib/laser_calibration.h"
#include "uwscan/laser/detector.h"
#include "uwscan/sensor/rig.h"

namespace uwscan {

struct CameraPipelineOptions {
  std::filesystem::path images;  // in air
  std::filesystem::path water;   // optional, flat port only
  BoardSpec board;
  CameraModelId model = CameraModelId::kPinhole;
  double n_glass = 1.52, d_glass = 0.006;  // flat port: known glass
  double n_water = 1.333;
  bool estimate_n_water = false;
  // The in-air images were taken without the port (thesis §6.1: camera in
  // front of an aquarium, calibrated in air without its window). The joint
  // air + water fit assumes the same port in both sets, so the result is
  // then the in-water refinement of the in-air lens.
  bool air_without_port = false;
  FlatPortResidualType residual = FlatPortResidualType::kExact;
  DetectionOptions detection;
  CameraCalibrationOptions calibration;
  std::string camera_name = "cam0";
  void Check() const;
};

struct CameraPipelineResult {
  CameraCalibrationResult result;  // the final stage
  nlohmann::json report;           // detections, every stage, comparisons
  cv::Mat residual_plot;
  std::vector<std::string> log;  // one line per stage, for the terminal
};

// Pinhole: detection + stage 1. Flat port: + stage 2; with water images the
// sequential refinement (Tab. 4.11) and the joint air + water bundle (the
// result, unless air_without_port), plus a pinhole calibrated under water
// for comparison.
CameraPipelineResult RunCameraCalibration(const CameraPipelineOptions& options);

struct LaserPipelineOptions {
  std::filesystem::path images;
  BoardSpec board;
  DetectionOptions detection;
  LaserCalibrationOptions calibration;
  // Plain planar target around the checkerboard's outer squares (m): laser
  // points there count too.
  double target_margin_m = 0.0;
  // Views whose board corners the calibrated camera cannot fit better than
  // this are left out (a wrong corner would tilt the board plane).
  double max_board_rms_px = 1.0;
  int laser_channel = laser::kGreen;  // from the laser's wavelength
  // Servo variant (§6.5): the axis and each image's servo angle (by file
  // name); every image with a board must have an angle.
  std::optional<ServoAxis> servo;
  std::map<std::string, double> servo_angles_rad;
};

// Reads "file,angle_deg" lines (a header line is allowed); throws
// uwscan::Error naming the file and line.
std::map<std::string, double> ReadServoAngles(const std::filesystem::path& path);

struct LaserPipelineResult {
  LaserCalibrationResult result;
  nlohmann::json report;
};

LaserPipelineResult RunLaserCalibration(const Camera& camera, const LaserPipelineOptions& options);

}  // namespace uwscan
