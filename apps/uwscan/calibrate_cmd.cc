// uwscan calibrate camera | laser: checkerboard calibration of a flat-port
// camera (in air, refined in water) and of a line laser (thesis §4.4).
#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "commands.h"
#include "uwscan/calib/board_pose.h"
#include "uwscan/calib/calibration_report.h"
#include "uwscan/calib/camera_calibration.h"
#include "uwscan/calib/checkerboard.h"
#include "uwscan/calib/detection_benchmark.h"
#include "uwscan/calib/laser_calibration.h"
#include "uwscan/calib/laser_points.h"
#include "uwscan/io/rig_yaml.h"
#include "uwscan/util/error.h"

namespace uwscan::cli {
namespace {

namespace fs = std::filesystem;

struct CameraArgs {
  std::string images, board, model = "pinhole", water, glass, out, report, camera = "cam0";
  std::string detector = "sb", residual = "exact";
  double water_index = 1.333;
  bool estimate_water_index = false;
  double max_view_rms = 1.0;
  bool quiet = false;
};

struct LaserArgs {
  std::string rig, images, board, out, report, camera, laser = "laser0", detector = "sb";
  bool quiet = false;
};

CornerDetector ParseDetector(const std::string& name) {
  if (name == "sb") return CornerDetector::kSectorBased;
  if (name == "classic") return CornerDetector::kClassic;
  throw UsageError("--detector must be sb or classic, got '" + name + "'");
}

void PrintDetections(const std::string& label, const FolderDetection& detection) {
  std::fprintf(stderr, "%s: board found in %zu of %zu image(s)\n", label.c_str(),
               detection.set.views.size(), detection.images.size());
  for (const BoardDetection& d : detection.images) {
    if (!d.found) std::fprintf(stderr, "  %s: %s\n", d.name.c_str(), d.reason.c_str());
  }
}

void PrintResult(const CameraCalibrationResult& r) {
  std::printf("%-15s rms %.4f px, %d views used, fx %.3f fy %.3f cx %.3f cy %.3f", r.stage.c_str(),
              r.rms_px, r.used_views, r.camera.intrinsics[0], r.camera.intrinsics[1],
              r.camera.intrinsics[2], r.camera.intrinsics[3]);
  if (r.camera.IsFlatPort()) {
    std::printf(", d_air %.2f mm, tilt %.3f deg", r.camera.port.d_air * 1e3,
                r.camera.port.TiltRad() * 180.0 / M_PI);
  }
  std::printf("\n");
  for (const ViewReport& v : r.views) {
    if (!v.used) std::printf("  dropped %s: %s\n", v.name.c_str(), v.dropped_reason.c_str());
  }
}

void RunCalibrateCamera(const CameraArgs& args) {
  const BoardSpec board = BoardSpec::Parse(args.board);
  const auto model = CameraModelFromName(args.model);
  if (!model) throw UsageError("--model must be pinhole or flatport, got '" + args.model + "'");
  if (*model == CameraModelId::kPinhole && !args.water.empty()) {
    throw UsageError("--water needs --model flatport");
  }
  double n_glass = 0.0, d_glass = 0.0;
  if (*model == CameraModelId::kFlatPort) {
    char tail = 0;
    if (args.glass.empty() ||
        std::sscanf(args.glass.c_str(), "%lf,%lf%c", &n_glass, &d_glass, &tail) != 2) {
      throw UsageError("--model flatport needs --glass INDEX,THICKNESS_M (e.g. 1.52,0.006)");
    }
  }
  DetectionOptions detection_options;
  detection_options.detector = ParseDetector(args.detector);
  const FlatPortResidualType residual =
      args.residual == "taylor" ? FlatPortResidualType::kTaylor : FlatPortResidualType::kExact;
  if (args.residual != "taylor" && args.residual != "exact") {
    throw UsageError("--residual must be exact or taylor");
  }

  nlohmann::json report;
  report["board"] = board.ToString();
  report["detector"] = CornerDetectorName(detection_options.detector);
  const FolderDetection air = DetectBoardsInFolder(args.images, board, detection_options);
  if (!args.quiet) PrintDetections(args.images, air);
  report["detections"] = DetectionsToJson(air.images);

  CameraCalibrationOptions options;
  options.outliers.max_view_rms_px = args.max_view_rms;
  Camera camera;
  camera.name = args.camera;
  CameraCalibrationResult final_result = CalibratePinhole(air.set, camera, options);
  PrintResult(final_result);
  report["stages"].push_back(CameraResultToJson(final_result));

  if (*model == CameraModelId::kFlatPort) {
    FlatPortAirOptions air_options;
    air_options.common = options;
    air_options.n_glass = n_glass;
    air_options.d_glass = d_glass;
    const CameraCalibrationResult in_air =
        CalibrateFlatPortInAir(air.set, final_result, air_options);
    PrintResult(in_air);
    report["stages"].push_back(CameraResultToJson(in_air));
    final_result = in_air;
    final_result.camera.port.n_water = args.water_index;  // the medium it will be used in
    if (!args.water.empty()) {
      const FolderDetection water = DetectBoardsInFolder(args.water, board, detection_options);
      if (!args.quiet) PrintDetections(args.water, water);
      report["water_detections"] = DetectionsToJson(water.images);
      UWS_CHECK(water.set.width == air.set.width && water.set.height == air.set.height, args.water,
                ": water images are ", water.set.width, "x", water.set.height,
                " but air images are ", air.set.width, "x", air.set.height);
      WaterRefinementOptions water_options;
      water_options.common = options;
      water_options.n_water = args.water_index;
      water_options.estimate_n_water = args.estimate_water_index;
      water_options.residual = residual;
      // Sequential refinement as in Tab. 4.11, for the report ...
      const CameraCalibrationResult sequential =
          RefineFlatPortInWater(water.set, in_air.camera, water_options);
      PrintResult(sequential);
      report["stages"].push_back(CameraResultToJson(sequential));
      // ... and the joint air + water bundle as the result.
      final_result = CalibrateFlatPortJoint(air.set, in_air, water.set, water_options);
      PrintResult(final_result);
      report["stages"].push_back(CameraResultToJson(final_result));
      // A pinhole calibrated under water, the usual shortcut, for comparison.
      const CameraCalibrationResult pin_water = CalibratePinhole(water.set, camera, options);
      PrintResult(pin_water);
      report["pinhole_in_water"] = CameraResultToJson(pin_water);
      report["pinhole_vs_flatport"] = PinholeComparisonJson(final_result.camera, &pin_water.camera,
                                                            {0.3, 0.5, 1.0, 2.0, 3.0, 5.0}, 1.0);
    } else {
      report["pinhole_vs_flatport"] =
          PinholeComparisonJson(final_result.camera, nullptr, {0.3, 0.5, 1.0, 2.0, 3.0, 5.0}, 1.0);
    }
  }
  report["result"] = CameraResultToJson(final_result);
  Rig rig;
  rig.cameras.push_back(final_result.camera);
  WriteRigYaml(args.out, rig);
  if (!args.report.empty()) {
    const cv::Mat plot =
        DrawResidualField(final_result, final_result.camera.width, final_result.camera.height);
    WriteReport(args.report, "calibration", report, &plot);
  }
  std::printf("wrote %s\n", args.out.c_str());
}

void RunCalibrateLaser(const LaserArgs& args) {
  const BoardSpec board = BoardSpec::Parse(args.board);
  Rig rig = ReadRigYaml(args.rig);
  const Camera& camera = rig.CameraByName(args.camera);
  DetectionOptions detection_options;
  detection_options.detector = ParseDetector(args.detector);
  const FolderDetection detection = DetectBoardsInFolder(args.images, board, detection_options);
  if (!args.quiet) PrintDetections(args.images, detection);
  UWS_CHECK(detection.set.width == camera.width && detection.set.height == camera.height,
            args.images, ": images are ", detection.set.width, "x", detection.set.height,
            " but camera '", camera.name, "' in ", args.rig, " is ", camera.width, "x",
            camera.height);
  std::vector<LaserView> views;
  for (const ViewCorners& view : detection.set.views) {
    const auto pose = EstimateBoardPose(camera, board, view.corners);
    if (!pose) {
      std::fprintf(stderr, "  %s: no board pose\n", view.name.c_str());
      continue;
    }
    const cv::Mat image = cv::imread((fs::path(args.images) / view.name).string());
    LaserView laser_view;
    laser_view.name = view.name;
    laser_view.camera_from_board = pose->camera_from_board;
    laser_view.laser_pixels = ExtractLaserPixels(image, board, view.corners);
    views.push_back(laser_view);
  }
  LaserCalibrationOptions options;
  int laser_index = -1;
  for (size_t i = 0; i < rig.lasers.size(); ++i) {
    if (rig.lasers[i].name == args.laser) laser_index = static_cast<int>(i);
  }
  if (laser_index >= 0)
    options.nominal_camera_from_laser = rig.lasers[laser_index].camera_from_laser;
  const LaserCalibrationResult result = CalibrateLaser(camera, views, options);
  std::printf(
      "laser %s: %d/%d points inliers, plane rms %.3f mm, sheet rms %.3f mm, baseline "
      "%.2f mm, p1 %.5f\n",
      args.laser.c_str(), result.inliers, result.points, result.plane_rms_m * 1e3,
      result.sheet_rms_m * 1e3, result.baseline_m * 1e3, result.laser.p1);
  LineProjector laser = result.laser;
  laser.name = args.laser;
  if (laser_index >= 0) {
    laser.wavelength_nm = rig.lasers[laser_index].wavelength_nm;
    rig.lasers[laser_index] = laser;
  } else {
    rig.lasers.push_back(laser);
  }
  WriteRigYaml(args.out, rig);
  if (!args.report.empty()) {
    nlohmann::json report = {{"laser", LaserResultToJson(result)},
                             {"detections", DetectionsToJson(detection.images)}};
    WriteReport(args.report, "laser_calibration", report, nullptr);
  }
  std::printf("wrote %s\n", args.out.c_str());
}

}  // namespace

void RegisterCalibrateCommands(CLI::App& app) {
  auto* calibrate = app.add_subcommand("calibrate", "Calibrate cameras and lasers (thesis §4.4)");
  calibrate->require_subcommand(1);

  auto camera_args = std::make_shared<CameraArgs>();
  auto* camera = calibrate->add_subcommand(
      "camera", "Pinhole or flat-port camera from checkerboard images (in air, refined in water)");
  camera->add_option("--images", camera_args->images, "folder of in-air board images")->required();
  camera->add_option("--board", camera_args->board, "COLSxROWS:SQUARE_M (inner corners)")
      ->required();
  camera->add_option("--model", camera_args->model, "pinhole | flatport")->capture_default_str();
  camera->add_option("--water", camera_args->water, "folder of under-water board images");
  camera->add_option("--glass", camera_args->glass, "port glass INDEX,THICKNESS_M (flatport)");
  camera->add_option("--water-index", camera_args->water_index, "refraction index of the water")
      ->capture_default_str();
  camera->add_flag("--estimate-water-index", camera_args->estimate_water_index,
                   "estimate the water index from the water images (Tab. 4.11)");
  camera
      ->add_option("--residual", camera_args->residual,
                   "flat-port residual in water: exact | taylor (centred at the corner)")
      ->capture_default_str();
  camera->add_option("--detector", camera_args->detector, "sb (findChessboardCornersSB) | classic")
      ->capture_default_str();
  camera
      ->add_option("--max-view-rms", camera_args->max_view_rms,
                   "drop views above this RMS (px) or 3x the median")
      ->capture_default_str();
  camera->add_option("--camera", camera_args->camera, "camera name in the rig")
      ->capture_default_str();
  camera->add_option("--out", camera_args->out, "rig.yaml to write")->required();
  camera->add_option("--report", camera_args->report, "folder for calibration.json and the PNG");
  camera->add_flag("--quiet", camera_args->quiet, "no per-image messages");
  camera->callback([camera_args] { RunCalibrateCamera(*camera_args); });

  auto laser_args = std::make_shared<LaserArgs>();
  auto* laser = calibrate->add_subcommand(
      "laser", "Line laser from board images with the laser on, at two or more distances");
  laser->add_option("--rig", laser_args->rig, "rig.yaml with the calibrated camera")->required();
  laser->add_option("--images", laser_args->images, "folder of board images with the laser on")
      ->required();
  laser->add_option("--board", laser_args->board, "COLSxROWS:SQUARE_M (inner corners)")->required();
  laser->add_option("--camera", laser_args->camera, "camera name (default: the first)");
  laser
      ->add_option("--laser", laser_args->laser,
                   "laser name (its pose, if present, is the "
                   "nominal projector centre)")
      ->capture_default_str();
  laser->add_option("--detector", laser_args->detector, "sb | classic")->capture_default_str();
  laser->add_option("--out", laser_args->out, "rig.yaml to write")->required();
  laser->add_option("--report", laser_args->report, "folder for laser_calibration.json");
  laser->add_flag("--quiet", laser_args->quiet, "no per-image messages");
  laser->callback([laser_args] { RunCalibrateLaser(*laser_args); });

  auto* bench = calibrate->add_subcommand(
      "detect-bench", "Detection rate and corner error of both detectors on rendered boards");
  auto trials = std::make_shared<int>(10);
  bench->add_option("--trials", *trials, "board poses per condition")->capture_default_str();
  bench->callback([trials] {
    if (*trials < 1) throw UsageError("--trials must be >= 1");
    const auto rows =
        RunDetectionBenchmark(BoardSpec{9, 6, 0.03}, StandardDetectionConditions(), *trials, 1);
    std::printf("%s", DetectionBenchmarkMarkdown(rows).c_str());
  });
}

}  // namespace uwscan::cli
