#include "uwscan/calib/calibration_pipeline.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "uwscan/calib/board_pose.h"
#include "uwscan/calib/calibration_report.h"
#include "uwscan/calib/laser_points.h"
#include "uwscan/io/image.h"
#include "uwscan/util/csv.h"
#include "uwscan/util/error.h"

namespace uwscan {
namespace {

std::string Summary(const CameraCalibrationResult& r) {
  char line[512];
  int n = std::snprintf(line, sizeof(line),
                        "%-15s rms %.4f px, %d views used, fx %.3f fy %.3f cx %.3f cy %.3f",
                        r.stage.c_str(), r.rms_px, r.used_views, r.camera.intrinsics[0],
                        r.camera.intrinsics[1], r.camera.intrinsics[2], r.camera.intrinsics[3]);
  if (r.camera.IsFlatPort() && n > 0 && n < static_cast<int>(sizeof(line))) {
    std::snprintf(line + n, sizeof(line) - n, ", d_air %.2f mm, tilt %.3f deg, n_water %.4f",
                  r.camera.port.d_air * 1e3, r.camera.port.TiltRad() * 180.0 / M_PI,
                  r.camera.port.n_water);
  }
  std::string text = line;
  for (const ViewReport& v : r.views) {
    if (!v.used) text += "\n  dropped " + v.name + ": " + v.dropped_reason;
  }
  return text;
}

std::string DetectionSummary(const std::filesystem::path& folder, const FolderDetection& d) {
  std::string text = folder.string() + ": board found in " + std::to_string(d.set.views.size()) +
                     " of " + std::to_string(d.images.size()) + " image(s)";
  for (const BoardDetection& b : d.images) {
    if (!b.found) text += "\n  " + b.name + ": " + b.reason;
  }
  return text;
}

}  // namespace

void CameraPipelineOptions::Check() const {
  board.Check();
  calibration.Check();
  detection.Check();
  if (model == CameraModelId::kPinhole && !water.empty()) {
    throw UsageError("water images need the flat-port model");
  }
  if (air_without_port && (model != CameraModelId::kFlatPort || water.empty())) {
    throw UsageError(
        "--air-without-port needs --model flatport and --water images: the port is "
        "seen only through the water");
  }
  UWS_CHECK(n_glass >= 1.0 && n_glass < 3.0, "glass index must be in [1, 3), got ", n_glass);
  UWS_CHECK(d_glass > 0.0 && d_glass < 0.2, "glass thickness must be in (0, 0.2) m, got ", d_glass);
  UWS_CHECK(n_water >= 1.0 && n_water < 2.0, "water index must be in [1, 2), got ", n_water);
}

CameraPipelineResult RunCameraCalibration(const CameraPipelineOptions& options) {
  options.Check();
  CameraPipelineResult out;
  nlohmann::json& report = out.report;
  report["board"] = options.board.ToString();
  report["detector"] = CornerDetectorName(options.detection.detector);
  const FolderDetection air =
      DetectBoardsInFolder(options.images, options.board, options.detection);
  out.log.push_back(DetectionSummary(options.images, air));
  report["detections"] = DetectionsToJson(air.images);

  Camera camera;
  camera.name = options.camera_name;
  CameraCalibrationResult result = CalibratePinhole(air.set, camera, options.calibration);
  out.log.push_back(Summary(result));
  report["stages"].push_back(CameraResultToJson(result));
  const std::vector<double> ranges = {0.3, 0.5, 1.0, 2.0, 3.0, 5.0};

  if (options.model == CameraModelId::kFlatPort) {
    const CameraCalibrationResult pinhole = result;
    FlatPortAirOptions air_options;
    air_options.common = options.calibration;
    air_options.n_glass = options.n_glass;
    air_options.d_glass = options.d_glass;
    if (options.air_without_port) {
      // The air images show no port: the flat-port camera starts from the
      // pinhole one with the given glass, d_air and normal come from water.
      result.camera.model = CameraModelId::kFlatPort;
      result.camera.port.normal = Eigen::Vector3d::UnitZ();
      result.camera.port.d_air = air_options.d_air;
      result.camera.port.d_glass = air_options.d_glass;
      result.camera.port.n_air = air_options.n_air;
      result.camera.port.n_glass = air_options.n_glass;
    } else {
      result = CalibrateFlatPortInAir(air.set, pinhole, air_options);
      out.log.push_back(Summary(result));
      report["stages"].push_back(CameraResultToJson(result));
    }
    const CameraCalibrationResult in_air = result;
    result.camera.port.n_water = options.n_water;  // the medium it will be used in
    if (!options.water.empty()) {
      const FolderDetection water =
          DetectBoardsInFolder(options.water, options.board, options.detection);
      out.log.push_back(DetectionSummary(options.water, water));
      report["water_detections"] = DetectionsToJson(water.images);
      UWS_CHECK(water.set.width == air.set.width && water.set.height == air.set.height,
                options.water.string(), ": water images are ", water.set.width, "x",
                water.set.height, " but air images are ", air.set.width, "x", air.set.height);
      // The usual shortcut, for comparison: a pinhole calibrated under
      // water. Its focal length is about n_water times the lens's in air
      // (paraxial refraction at the flat port): much less, and the two
      // folders are swapped or the "water" views were taken dry.
      const CameraCalibrationResult pin_water =
          CalibratePinhole(water.set, camera, options.calibration);
      const double magnification = pin_water.camera.intrinsics[0] / pinhole.camera.intrinsics[0];
      UWS_CHECK(magnification >= 1.0 + 0.3 * (options.n_water - 1.0), options.water.string(),
                ": a pinhole fitted to these views has ", fmt::format("{:.3f}", magnification),
                " times the focal length of one fitted to ", options.images.string(),
                ", where water behind a flat port gives about ",
                fmt::format("{:.2f}", options.n_water), ": ",
                magnification < 1.0 ? "are --images (in air) and --water swapped?"
                                    : "were these views taken in air, not in water?");
      WaterRefinementOptions water_options;
      water_options.common = options.calibration;
      water_options.n_water = options.n_water;
      water_options.estimate_n_water = options.estimate_n_water;
      water_options.residual = options.residual;
      const CameraCalibrationResult sequential =
          RefineFlatPortInWater(water.set, in_air.camera, water_options);
      out.log.push_back(Summary(sequential));
      report["stages"].push_back(CameraResultToJson(sequential));
      result = options.air_without_port
                   ? CalibrateFlatPortJointPortlessAir(air.set, pinhole, water.set,
                                                       sequential.camera, water_options)
                   : CalibrateFlatPortJoint(air.set, in_air, water.set, water_options);
      out.log.push_back(Summary(result));
      report["stages"].push_back(CameraResultToJson(result));
      out.log.push_back(Summary(pin_water) + "  (pinhole on the water images)");
      report["pinhole_in_water"] = CameraResultToJson(pin_water);
      report["pinhole_vs_flatport"] =
          PinholeComparisonJson(result.camera, &pin_water.camera, ranges, 1.0);
    } else {
      report["pinhole_vs_flatport"] = PinholeComparisonJson(result.camera, nullptr, ranges, 1.0);
    }
  }
  report["result"] = CameraResultToJson(result);
  out.residual_plot = DrawResidualField(result, result.camera.width, result.camera.height);
  out.result = result;
  return out;
}

LaserPipelineResult RunLaserCalibration(const Camera& camera, const LaserPipelineOptions& options) {
  DetectionOptions board_detection = options.detection;
  board_detection.ignore_channel = options.laser_channel;  // the board without the line
  const FolderDetection detection =
      DetectBoardsInFolder(options.images, options.board, board_detection);
  UWS_CHECK(detection.set.width == camera.width && detection.set.height == camera.height,
            options.images.string(), ": ",
            ImageSizeMismatch(camera, detection.set.width, detection.set.height));
  std::vector<LaserView> views;
  nlohmann::json view_list = nlohmann::json::array();
  for (const ViewCorners& view : detection.set.views) {
    const auto pose = EstimateBoardPose(camera, options.board, view.corners);
    if (!pose) {
      view_list.push_back({{"image", view.name}, {"used", false}, {"reason", "no board pose"}});
      continue;
    }
    if (pose->rms_px > options.max_board_rms_px) {
      char reason[128];
      std::snprintf(reason, sizeof(reason), "board pose RMS %.2f px > %.2f px (corners wrong?)",
                    pose->rms_px, options.max_board_rms_px);
      view_list.push_back({{"image", view.name},
                           {"used", false},
                           {"reason", reason},
                           {"board_rms_px", pose->rms_px}});
      continue;
    }
    const std::filesystem::path file = options.images / view.name;
    cv::Mat image = cv::imread(file.string(), cv::IMREAD_UNCHANGED);
    UWS_CHECK(!image.empty(), file.string(), ": cannot read the image");
    PrepareFrame(&image, 16, file);  // an alpha channel dropped
    LaserView laser_view;
    laser_view.name = view.name;
    laser_view.camera_from_board = pose->camera_from_board;
    laser_view.laser_pixels = DetectLaserOnTarget(
        DemosaicToBgr(image, camera.bayer),
        TargetOutline(camera, options.board, pose->camera_from_board, options.target_margin_m),
        options.laser_channel);
    if (options.servo) {
      const auto angle = options.servo_angles_rad.find(view.name);
      UWS_CHECK(angle != options.servo_angles_rad.end(), options.images.string(), ": image '",
                view.name, "' has no servo angle");
      laser_view.servo_angle_rad = angle->second;
    }
    view_list.push_back({{"image", view.name},
                         {"used", true},
                         {"board_rms_px", pose->rms_px},
                         {"range_m", pose->camera_from_board.translation.norm()},
                         {"laser_pixels", laser_view.laser_pixels.size()}});
    views.push_back(laser_view);
  }
  LaserPipelineResult out;
  try {
    out.result = CalibrateLaser(camera, views, options.calibration,
                                options.servo ? &*options.servo : nullptr);
  } catch (const Error& e) {
    // Say what each image contributed: that is what the user has to fix.
    std::string text = e.what();
    for (const nlohmann::json& v : view_list) {
      text += "\n  " + v["image"].get<std::string>() + ": ";
      if (!v["used"].get<bool>()) {
        text += v["reason"].get<std::string>();
        continue;
      }
      char line[96];
      std::snprintf(line, sizeof(line), "%d laser points, board at %.3f m",
                    v["laser_pixels"].get<int>(), v["range_m"].get<double>());
      text += line;
    }
    for (const BoardDetection& b : detection.images)
      if (!b.found) text += "\n  " + b.name + ": " + b.reason;
    throw Error(text);
  }
  out.report = {{"laser", LaserResultToJson(out.result)},
                {"views", view_list},
                {"detections", DetectionsToJson(detection.images)}};
  return out;
}

std::map<std::string, double> ReadServoAngles(const std::filesystem::path& path) {
  std::ifstream in(path);
  UWS_CHECK(in, path.string(), ": cannot open the servo angle file");
  std::map<std::string, double> angles;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (number == 1) StripByteOrderMark(line);
    if (line.empty() || line[0] == '#') continue;
    const size_t comma = line.find(',');
    char* end = nullptr;
    const double degrees =
        comma == std::string::npos ? 0.0 : std::strtod(line.c_str() + comma + 1, &end);
    if (comma == std::string::npos || end == line.c_str() + comma + 1 ||
        (end && *end != '\0' && *end != '\r')) {
      if (number == 1) continue;  // header
      UWS_THROW(path.string(), ":", number, ": expected 'file,angle_deg', got '", line, "'");
    }
    UWS_CHECK(std::isfinite(degrees) && std::abs(degrees) <= 360.0, path.string(), ":", number,
              ": the angle must be a number of degrees in [-360, 360], got '",
              line.substr(comma + 1), "'");
    UWS_CHECK(angles.emplace(line.substr(0, comma), degrees * M_PI / 180.0).second, path.string(),
              ":", number, ": '", line.substr(0, comma), "' is given an angle twice");
  }
  UWS_CHECK(!angles.empty(), path.string(), ": no servo angles");
  // Radians read as degrees (frames.csv takes radians) put every view
  // within a degree or so: the servo would not have turned between them.
  const auto [lowest, highest] =
      std::minmax_element(angles.begin(), angles.end(),
                          [](const auto& a, const auto& b) { return a.second < b.second; });
  const double span_deg = (highest->second - lowest->second) * 180.0 / M_PI;
  UWS_CHECK(angles.size() < 2 || span_deg >= 1.0, path.string(), ": the servo angles span ",
            span_deg, " degrees (", lowest->first, " to ", highest->first,
            "): the servo must turn between the views; in radians? this file takes degrees");
  return angles;
}

}  // namespace uwscan
