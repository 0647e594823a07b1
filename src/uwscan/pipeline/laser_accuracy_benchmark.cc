#include "uwscan/pipeline/laser_accuracy_benchmark.h"

#include <cstdio>
#include <sstream>

#include "uwscan/pipeline/laser_detect.h"
#include "uwscan/sim/scenario.h"
#include "uwscan/util/error.h"

namespace uwscan {

void LaserAccuracyBenchmarkOptions::Check() const {
  UWS_CHECK(width >= 64 && height >= 48, "laser accuracy: resolution too small");
  UWS_CHECK(frames >= 1, "laser accuracy: --frames must be >= 1");
  UWS_CHECK(!turbidities.empty(), "laser accuracy: no turbidity given");
}

std::vector<LaserAccuracyRow> RunLaserAccuracyBenchmark(const LaserAccuracyBenchmarkOptions& options) {
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
      const auto layout = laser::LayoutFor(camera.bayer, camera.bayer == "none" ? 3 : 1);
      std::vector<LaserAccuracy> totals(3);
      for (int frame = 0; frame < scenario.frames; ++frame) {
        const sim::FrameState state = scenario.FrameAt(trajectory, frame);
        const sim::RenderedFrame rendered = renderer.Render(state);
        std::vector<Eigen::Vector2d> truth;
        for (const auto& p : renderer.LaserGroundTruth(state, 0.5)) truth.push_back(p.pixel);
        int m = 0;
        for (const auto method : {laser::Method::kThesis, laser::Method::kCentreOfGravity,
                                  laser::Method::kArgmax}) {
          detector.method = method;
          const auto detection = laser::DetectLaserLine(rendered.image, layout, detector);
          std::vector<Eigen::Vector2d> detected;
          for (const auto& p : detection.points) detected.emplace_back(p.u, p.v);
          totals[m++].Add(EvaluateLaserFrame(truth, detected, detector.scan_rows));
        }
      }
      int m = 0;
      for (const char* method : {"thesis", "cog", "argmax"}) {
        rows.push_back({turbidity, led, method, totals[m++]});
      }
    }
  }
  return rows;
}

std::string LaserAccuracyToMarkdown(const std::vector<LaserAccuracyRow>& rows) {
  std::ostringstream out;
  out << "| water | LED | method | RMS (px) | completeness | outliers | detections |\n"
      << "|---|---|---|---|---|---|---|\n";
  char line[256];
  for (const auto& r : rows) {
    std::snprintf(line, sizeof(line), "| %s | %s | %s | %.3f | %.1f %% | %.2f %% | %ld |\n",
                  r.turbidity.c_str(), r.led ? "on" : "off", r.method.c_str(), r.accuracy.Rms(),
                  100.0 * r.accuracy.Completeness(), 100.0 * r.accuracy.OutlierRate(),
                  r.accuracy.detections);
    out << line;
  }
  return out.str();
}

}  // namespace uwscan
