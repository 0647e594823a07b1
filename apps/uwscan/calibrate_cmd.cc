// uwscan calibrate camera | laser: checkerboard calibration of a flat-port
// camera (in air, refined in water) and of a line laser (thesis §4.4).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <sstream>
#include <utility>
#include <vector>

#include "commands.h"
#include "uwscan/calib/calibration_pipeline.h"
#include "uwscan/calib/calibration_report.h"
#include "uwscan/calib/detection_benchmark.h"
#include "uwscan/io/rig_yaml.h"
#include "uwscan/util/atomic_file.h"
#include "uwscan/util/error.h"

namespace uwscan::cli {
namespace {

namespace fs = std::filesystem;

// Board view checks shared by both subcommands (dim or soft images need
// looser ones; every rejection is reported with its reason).
struct BoardCheckArgs {
  double max_edge_width_px = 6.0;
  double min_contrast = 15.0;
  void AddTo(CLI::App* app) {
    app->add_option("--max-edge-width", max_edge_width_px,
                    "reject views whose board edges rise over more pixels (10-90 %)")
        ->capture_default_str();
    app->add_option("--min-contrast", min_contrast,
                    "reject views with less contrast between black and white squares (grey levels)")
        ->capture_default_str();
  }
  void ApplyTo(DetectionOptions* detection) const {
    if (!(max_edge_width_px > 0.0)) throw UsageError("--max-edge-width must be positive");
    if (!(min_contrast >= 0.0)) throw UsageError("--min-contrast must be >= 0");
    detection->max_edge_width_px = max_edge_width_px;
    detection->min_contrast = min_contrast;
  }
};

struct CameraArgs {
  std::string images, board, model = "pinhole", water, glass, out, report, camera = "cam0", rig;
  std::string detector = "sb", residual = "exact";
  double water_index = 1.333;
  bool estimate_water_index = false;
  bool air_without_port = false;
  double max_view_rms = 1.0;
  BoardCheckArgs board_checks;
  bool quiet = false;
};

struct LaserArgs {
  std::string rig, images, board, out, report, camera, laser = "laser0", detector = "sb";
  std::string servo_angles, servo_axis;
  double target_margin_m = 0.0;
  BoardCheckArgs board_checks;
  bool quiet = false;
};

CornerDetector ParseDetector(const std::string& name) {
  const auto detector = CornerDetectorFromName(name);
  if (!detector)
    throw UsageError("--detector must be sb, sb-subpix or classic, got '" + name + "'");
  return *detector;
}

// A report written among the board images (`--report` the --images or
// --water folder) puts its PNG there, and the next calibration of that
// folder reads it as a board image and fails on its size.
void RefuseReportAmongImages(const std::string& report,
                             const std::vector<std::pair<const char*, std::string>>& folders) {
  for (const auto& [option, folder] : folders) {
    UWS_USAGE_CHECK(!SameExistingPath(report, folder), "--report ", report, " is the ", option,
                    " folder: its PNG would be read as a board image; give another folder");
  }
}

void RunCalibrateCamera(const CameraArgs& args) {
  CameraPipelineOptions options;
  options.board = BoardSpec::Parse(args.board);
  const auto model = CameraModelFromName(args.model);
  if (!model) throw UsageError("--model must be pinhole or flatport, got '" + args.model + "'");
  options.model = *model;
  if (*model == CameraModelId::kPinhole && !args.water.empty()) {
    throw UsageError("--water needs --model flatport");
  }
  if (*model == CameraModelId::kFlatPort) {
    char tail = 0;
    if (args.glass.empty() || std::sscanf(args.glass.c_str(), "%lf,%lf%c", &options.n_glass,
                                          &options.d_glass, &tail) != 2) {
      throw UsageError("--model flatport needs --glass INDEX,THICKNESS_M (e.g. 1.52,0.006)");
    }
  }
  if (args.residual != "taylor" && args.residual != "exact") {
    throw UsageError("--residual must be exact or taylor");
  }
  options.residual =
      args.residual == "taylor" ? FlatPortResidualType::kTaylor : FlatPortResidualType::kExact;
  options.images = args.images;
  options.water = args.water;
  options.n_water = args.water_index;
  options.estimate_n_water = args.estimate_water_index;
  options.air_without_port = args.air_without_port;
  options.detection.detector = ParseDetector(args.detector);
  options.detection.progress = !args.quiet;
  args.board_checks.ApplyTo(&options.detection);
  options.calibration.outliers.max_view_rms_px = args.max_view_rms;
  options.camera_name = args.camera;
  try {
    options.Check();
  } catch (const UsageError&) {
    throw;
  } catch (const Error& e) {
    throw UsageError(e.what());
  }
  // The report's folder is made before the (long) calibration, so that a
  // place it cannot be made fails at once; it goes again if the run fails.
  RefuseReportAmongImages(args.report, {{"--images", args.images}, {"--water", args.water}});
  std::optional<OutputFolder> report_folder;
  if (!args.report.empty()) report_folder.emplace(args.report);
  const CameraPipelineResult out = RunCameraCalibration(options);
  for (const std::string& line : out.log) {
    if (!args.quiet || line.find("image(s)") == std::string::npos)
      std::printf("%s\n", line.c_str());
  }
  // With --rig the other cameras and the lasers are kept and the named
  // camera is replaced (or added), keeping its rig_from_camera.
  Rig rig;
  if (!args.rig.empty()) rig = ReadRigYaml(args.rig);
  Camera calibrated = out.result.camera;
  bool replaced = false;
  for (Camera& existing : rig.cameras) {
    if (existing.name != calibrated.name) continue;
    calibrated.rig_from_camera = existing.rig_from_camera;
    calibrated.bayer = existing.bayer;
    existing = calibrated;
    replaced = true;
  }
  if (!replaced) rig.cameras.push_back(calibrated);
  StagedFiles files;  // the report and the rig: all or none
  if (report_folder)
    AddReportFiles(args.report, "calibration", out.report, &out.residual_plot, &files);
  files.Add(args.out, RigToYaml(rig));
  files.Commit();
  if (report_folder) report_folder->Keep();
  std::printf("wrote %s\n", args.out.c_str());
}

void RunCalibrateLaser(const LaserArgs& args) {
  LaserPipelineOptions options;
  options.board = BoardSpec::Parse(args.board);
  options.images = args.images;
  options.detection.detector = ParseDetector(args.detector);
  options.detection.progress = !args.quiet;
  args.board_checks.ApplyTo(&options.detection);
  if (!(args.target_margin_m >= 0.0 && args.target_margin_m < 10.0))
    throw UsageError("--target-margin must be in [0, 10) m");
  options.target_margin_m = args.target_margin_m;
  Rig rig = ReadRigYaml(args.rig);
  const Camera& camera = rig.CameraByName(args.camera);
  int laser_index = -1;
  for (size_t i = 0; i < rig.lasers.size(); ++i) {
    if (rig.lasers[i].name == args.laser) laser_index = static_cast<int>(i);
  }
  if (laser_index >= 0) {
    options.calibration.nominal_camera_from_laser = rig.lasers[laser_index].camera_from_laser;
    options.laser_channel = laser::ChannelForWavelength(rig.lasers[laser_index].wavelength_nm);
  }
  if (args.servo_angles.empty() != args.servo_axis.empty()) {
    throw UsageError("--servo-angles and --servo-axis go together");
  }
  if (!args.servo_axis.empty()) {
    double v[6];
    char tail = 0;
    if (std::sscanf(args.servo_axis.c_str(), "%lf,%lf,%lf,%lf,%lf,%lf%c", &v[0], &v[1], &v[2],
                    &v[3], &v[4], &v[5], &tail) != 6 ||
        !std::all_of(std::begin(v), std::end(v), [](double x) { return std::isfinite(x); }) ||
        Eigen::Vector3d(v[3], v[4], v[5]).norm() < 1e-9) {
      throw UsageError(
          "--servo-axis must be PX,PY,PZ,DX,DY,DZ (camera frame, m; nonzero direction), got '" +
          args.servo_axis + "'");
    }
    options.servo = ServoAxis{Eigen::Vector3d(v[0], v[1], v[2]),
                              Eigen::Vector3d(v[3], v[4], v[5]).normalized()};
    options.servo_angles_rad = ReadServoAngles(args.servo_angles);
  }
  RefuseReportAmongImages(args.report, {{"--images", args.images}});
  std::optional<OutputFolder> report_folder;  // made first, as for the camera
  if (!args.report.empty()) report_folder.emplace(args.report);
  const LaserPipelineResult out = RunLaserCalibration(camera, options);
  const LaserCalibrationResult& result = out.result;
  std::printf(
      "laser %s: %d/%d points inliers, plane rms %.3f mm, sheet rms %.3f mm, baseline "
      "%.2f mm, sheet normal to camera x %.3f deg, p1 %.5f\n",
      args.laser.c_str(), result.inliers, result.points, result.plane_rms_m * 1e3,
      result.sheet_rms_m * 1e3, result.baseline_m * 1e3, result.sheet_angle_deg, result.laser.p1);
  LineProjector laser = result.laser;
  laser.name = args.laser;
  if (laser_index >= 0) {
    laser.wavelength_nm = rig.lasers[laser_index].wavelength_nm;
    rig.lasers[laser_index] = laser;
  } else {
    rig.lasers.push_back(laser);
  }
  StagedFiles files;  // the report and the rig: all or none
  if (report_folder) AddReportFiles(args.report, "laser_calibration", out.report, nullptr, &files);
  files.Add(args.out, RigToYaml(rig));
  files.Commit();
  if (report_folder) report_folder->Keep();
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
  camera->add_flag("--air-without-port", camera_args->air_without_port,
                   "in-air images taken without the port (§6.1 aquarium): the joint fit treats "
                   "them as straight-ray views sharing the lens with the water views");
  camera
      ->add_option("--residual", camera_args->residual,
                   "flat-port residual in water: exact | taylor (centred at the corner)")
      ->capture_default_str();
  camera
      ->add_option("--detector", camera_args->detector,
                   "sb (findChessboardCornersSB) | sb-subpix | classic")
      ->capture_default_str();
  camera
      ->add_option("--max-view-rms", camera_args->max_view_rms,
                   "drop views above this RMS (px) or 3x the median")
      ->capture_default_str();
  camera_args->board_checks.AddTo(camera);
  camera->add_option("--camera", camera_args->camera, "camera name in the rig")
      ->capture_default_str();
  camera->add_option("--rig", camera_args->rig,
                     "existing rig.yaml to update (other cameras and lasers are kept)");
  camera->add_option("--out", camera_args->out, "rig.yaml to write")->required();
  camera->add_option("--report", camera_args->report, "folder for calibration.json and the PNG");
  camera->add_flag("--quiet", camera_args->quiet, "no progress bar or per-image messages");
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
  laser->add_option("--detector", laser_args->detector, "sb | sb-subpix | classic")
      ->capture_default_str();
  laser_args->board_checks.AddTo(laser);
  laser
      ->add_option("--target-margin", laser_args->target_margin_m,
                   "plain planar target around the board's outer squares (m); laser points "
                   "there are used too")
      ->capture_default_str();
  laser->add_option("--servo-angles", laser_args->servo_angles,
                    "servo variant (§6.5): CSV 'file,angle_deg' per image of one sweep");
  laser->add_option("--servo-axis", laser_args->servo_axis,
                    "servo axis PX,PY,PZ,DX,DY,DZ in the camera frame (m)");
  laser->add_option("--out", laser_args->out, "rig.yaml to write")->required();
  laser->add_option("--report", laser_args->report, "folder for laser_calibration.json");
  laser->add_flag("--quiet", laser_args->quiet, "no progress bar or per-image messages");
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
