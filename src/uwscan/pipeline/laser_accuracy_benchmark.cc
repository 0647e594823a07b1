#include "uwscan/pipeline/laser_accuracy_benchmark.h"

#include <cmath>
#include <cstdio>
#include <optional>
#include <sstream>

#include "uwscan/laser/profile.h"
#include "uwscan/pipeline/laser_detect.h"
#include "uwscan/sim/scenario.h"
#include "uwscan/util/error.h"

namespace uwscan {

void LaserAccuracyBenchmarkOptions::Check() const {
  UWS_USAGE_CHECK(width >= 64 && height >= 48, "laser accuracy: resolution too small");
  UWS_USAGE_CHECK(frames >= 1, "laser accuracy: --frames must be >= 1");
  UWS_USAGE_CHECK(!turbidities.empty(), "laser accuracy: no turbidity given");
}

namespace {

// The true 3D point where the line crosses the detection's scan line, if the
// detection lies within 1 px of it (interpolated between truth samples).
std::optional<Eigen::Vector3d> TruePointOnScanLine(const std::vector<sim::LaserPoint>& truth,
                                                   const Eigen::Vector2d& pixel, bool scan_rows) {
  const int line_axis = scan_rows ? 1 : 0, along_axis = scan_rows ? 0 : 1;
  for (size_t i = 0; i + 1 < truth.size(); ++i) {
    const auto& a = truth[i];
    const auto& b = truth[i + 1];
    const double la = a.pixel[line_axis], lb = b.pixel[line_axis];
    const double line = pixel[line_axis];
    if ((la - line) * (lb - line) > 0 || std::abs(lb - la) > 3.0 || la == lb) continue;
    const double w = (line - la) / (lb - la);
    const double along = a.pixel[along_axis] + w * (b.pixel[along_axis] - a.pixel[along_axis]);
    if (std::abs(along - pixel[along_axis]) > 1.0) continue;
    return a.point_in_camera + w * (b.point_in_camera - a.point_in_camera);
  }
  return std::nullopt;
}

}  // namespace

std::vector<LaserAccuracyRow> RunLaserAccuracyBenchmark(
    const LaserAccuracyBenchmarkOptions& options) {
  options.Check();
  std::vector<LaserAccuracyRow> rows;
  for (const auto& turbidity : options.turbidities) {
    for (const bool led : {true, false}) {
      sim::ScenarioOptions scenario_options;
      scenario_options.width = options.width;
      scenario_options.height = options.height;
      scenario_options.frames = options.frames;
      scenario_options.seed = options.seed;
      scenario_options.turbidity = turbidity;
      sim::Scenario scenario = sim::MakeScenario("tank-target", scenario_options);
      if (!led) scenario.config.floods.clear();
      const sim::Renderer renderer(scenario.config);
      const sim::Trajectory trajectory(scenario.motion);
      const Camera& camera = renderer.camera();
      const auto& laser = scenario.config.rig.lasers.front();
      laser::DetectorOptions detector;
      detector.scan_rows = LaserLineIsVertical(camera, laser.camera_from_laser);
      detector.laser_channel = laser::ChannelForWavelength(laser.wavelength_nm);
      detector.albedo_channel = laser::AlbedoChannelFor(detector.laser_channel);  // as reconstruct
      const auto layout = laser::LayoutFor(camera.bayer, camera.bayer == "none" ? 3 : 1);
      std::vector<LaserAccuracy> totals(3);
      std::vector<double> profile_sum(3, 0.0);
      std::vector<long> profile_count(3, 0);
      for (int frame = 0; frame < scenario.frames; ++frame) {
        const sim::FrameState state = scenario.FrameAt(trajectory, frame);
        const sim::RenderedFrame rendered = renderer.Render(state);
        const auto truth_points = renderer.LaserGroundTruth(state, 0.5);
        std::vector<Eigen::Vector2d> truth;
        for (const auto& p : truth_points) truth.push_back(p.pixel);
        const Rigid3d camera_from_laser = renderer.CameraFromLaser(
            0, state.laser_angles_rad.empty() ? 0.0 : state.laser_angles_rad[0]);
        int m = 0;
        for (const auto method :
             {laser::Method::kThesis, laser::Method::kCentreOfGravity, laser::Method::kArgmax}) {
          detector.method = method;
          const auto detection = laser::DetectLaserLine(rendered.image, layout, detector);
          std::vector<Eigen::Vector2d> detected;
          for (const auto& p : detection.points) detected.emplace_back(p.u, p.v);
          totals[m].Add(EvaluateLaserFrame(truth, detected, detector.scan_rows));
          const auto profile =
              laser::TriangulateProfile(camera, laser, camera_from_laser, detection.points);
          for (const auto& p : profile.points) {
            if (const auto true_point =
                    TruePointOnScanLine(truth_points, p.pixel, detector.scan_rows)) {
              profile_sum[m] += (p.point_in_camera - *true_point).squaredNorm();
              ++profile_count[m];
            }
          }
          ++m;
        }
      }
      int m = 0;
      for (const char* method : {"thesis", "cog", "argmax"}) {
        rows.push_back({turbidity, led, method, totals[m],
                        profile_count[m] ? std::sqrt(profile_sum[m] / profile_count[m]) : 0.0,
                        profile_count[m]});
        ++m;
      }
    }
  }
  return rows;
}

std::string LaserAccuracyToMarkdown(const std::vector<LaserAccuracyRow>& rows) {
  std::ostringstream out;
  out << "| water | LED | method | RMS (px) | completeness | outliers | detections | profile RMS "
         "(mm) |\n"
      << "|---|---|---|---|---|---|---|---|\n";
  // An RMS over no detections is not 0: "-".
  const auto rms = [](bool any, double value) {
    char cell[32] = "-";
    if (any) std::snprintf(cell, sizeof(cell), "%.3f", value);
    return std::string(cell);
  };
  char line[256];
  for (const auto& r : rows) {
    std::snprintf(line, sizeof(line), "| %s | %s | %s | %s | %.1f %% | %.2f %% | %ld | %s |\n",
                  r.turbidity.c_str(), r.led ? "on" : "off", r.method.c_str(),
                  rms(r.accuracy.found > 0, r.accuracy.Rms()).c_str(),
                  100.0 * r.accuracy.Completeness(), 100.0 * r.accuracy.OutlierRate(),
                  r.accuracy.detections, rms(r.profile_points > 0, r.profile_rms_m * 1e3).c_str());
    out << line;
  }
  return out.str();
}

}  // namespace uwscan
