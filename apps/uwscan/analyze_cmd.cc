// uwscan analyze port: how far a pinhole model is from the rig's flat port.
#include <cmath>
#include <cstdio>
#include <iostream>

#include "commands.h"
#include "uwscan/eval/port_analysis.h"
#include "uwscan/io/rig_yaml.h"
#include "uwscan/util/error.h"

namespace uwscan::cli {
namespace {

struct AnalyzePortArgs {
  std::string rig, camera;
  double depth = 3.0;
  bool json = false;
};

void RunAnalyzePort(const AnalyzePortArgs& args) {
  CheckViewingDistanceOption("--depth", args.depth, 0.05);
  const Rig rig = ReadRigYaml(args.rig);
  const Camera& camera = rig.CameraByName(args.camera);
  UWS_CHECK(camera.IsFlatPort(), args.rig, ": camera '", camera.name,
            "' has model pinhole: there is no port to analyse");
  PinholeFitOptions options;
  options.depth_m = args.depth;
  const PinholeFit fit = FitPinholeToFlatPort(camera, options);
  const std::vector<double> depths = {0.5, 1.0, 2.0, 3.0, 5.0, 10.0, 20.0};
  const double half_diagonal = std::atan(std::hypot(camera.width / 2.0 / camera.intrinsics[0],
                                                    camera.height / 2.0 / camera.intrinsics[1]));

  std::printf("camera %s: %dx%d, f = %.1f px, port tilt %.3f deg, d_air %.2f mm, d_glass %.2f mm\n",
              camera.name.c_str(), camera.width, camera.height, camera.intrinsics[0],
              camera.port.TiltRad() * 180.0 / M_PI, camera.port.d_air * 1e3,
              camera.port.d_glass * 1e3);
  const auto& p = fit.pinhole;
  std::printf(
      "best pinhole at %.2f m: fx %.2f fy %.2f cx %.2f cy %.2f k1 %.4f k2 %.4f p1 %.2e p2 %.2e k3 "
      "%.4f\n",
      args.depth, p.intrinsics[0], p.intrinsics[1], p.intrinsics[2], p.intrinsics[3],
      p.distortion[0], p.distortion[1], p.distortion[2], p.distortion[3], p.distortion[4]);
  std::printf("pinhole model error over the image (px):\n");
  std::printf("  %8s %10s %10s %10s\n", "depth_m", "median", "p95", "max");
  for (double depth : depths) {
    const ErrorStats stats = PinholeErrorAtDepth(camera, fit.pinhole, depth);
    std::printf("  %8.2f %10.4f %10.4f %10.4f%s\n", depth, stats.median_px, stats.p95_px,
                stats.max_px, std::abs(depth - args.depth) < 1e-9 ? "  (fit depth)" : "");
  }
  std::printf("optimal d_air (eq. 4.27: the air gap that cancels refraction for one ray angle):\n");
  for (double degrees : {5.0, 15.0, 25.0, 35.0, half_diagonal * 180.0 / M_PI}) {
    std::printf("  ray at %5.1f deg%s: d_air %.2f mm\n", degrees,
                std::abs(degrees - half_diagonal * 180.0 / M_PI) < 1e-9 ? " (image corner)" : "",
                OptimalAirGap(camera.port, degrees * M_PI / 180.0) * 1e3);
  }
}

}  // namespace

void RegisterAnalyzeCommands(CLI::App& app) {
  auto* analyze = app.add_subcommand("analyze", "Analyse a rig");
  analyze->require_subcommand(1);
  auto args = std::make_shared<AnalyzePortArgs>();
  auto* port = analyze->add_subcommand(
      "port",
      "Error of the best pinhole approximation of a flat-port camera, and the optimal d_air");
  port->add_option("--rig", args->rig, "rig.yaml")->required();
  port->add_option("--camera", args->camera, "camera name (default: the first)");
  port->add_option("--depth", args->depth,
                   "distance (m) from the camera to the plane the pinhole is fitted on")
      ->capture_default_str();
  port->callback([args] { RunAnalyzePort(*args); });
}

}  // namespace uwscan::cli
