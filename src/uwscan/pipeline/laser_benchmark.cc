#include "uwscan/pipeline/laser_benchmark.h"

#include <chrono>
#include <opencv2/imgcodecs.hpp>

#include "uwscan/io/image.h"
#include "uwscan/io/rig_yaml.h"
#include "uwscan/laser/synthetic_line.h"
#include "uwscan/pipeline/laser_detect.h"
#include "uwscan/util/error.h"
#include "uwscan/util/stopwatch.h"

namespace uwscan {

void LaserBenchmarkOptions::Check() const {
  UWS_USAGE_CHECK(width >= 64 && height >= 64, "bench laser: frames must be at least 64x64");
  UWS_USAGE_CHECK(frames >= 1 && repetitions >= 1,
                  "bench laser: --frames and --repetitions must be >= 1");
}

std::vector<cv::Mat> MakeLaserBenchmarkFrames(const LaserBenchmarkOptions& options) {
  options.Check();
  std::vector<cv::Mat> frames;
  for (int i = 0; i < options.frames; ++i) {
    laser::SyntheticLineOptions line;
    line.width = options.width;
    line.height = options.height;
    line.layout = options.bayer ? laser::ColourLayout::kBayerRggb : laser::ColourLayout::kMono;
    line.u0 = options.width * (0.3 + 0.4 * i / std::max(1, options.frames - 1));
    line.curvature = 2e-4;
    line.seed = 100 + i;
    frames.push_back(laser::RenderSyntheticLine(line).image);
  }
  return frames;
}

std::vector<cv::Mat> LoadDatasetFrames(const std::string& dataset, int max_frames,
                                       laser::ColourLayout* layout,
                                       laser::DetectorOptions* detector) {
  const std::filesystem::path root(dataset);
  const Rig rig = ReadRigYaml(root / "rig.yaml");
  const Camera& camera = rig.cameras.front();
  if (!rig.lasers.empty()) {
    detector->scan_rows = LaserLineIsVertical(camera, rig.CameraFromLaser(0, 0));
    detector->laser_channel = laser::ChannelForWavelength(rig.lasers.front().wavelength_nm);
  }
  std::vector<cv::Mat> frames;
  for (const auto& path : ListImageFiles(root / "frames")) {
    if (static_cast<int>(frames.size()) >= max_frames) break;
    cv::Mat image = cv::imread(path.string(), cv::IMREAD_UNCHANGED);
    UWS_CHECK(!image.empty(), path.string(), ": unreadable image");
    frames.push_back(image);
  }
  *layout = laser::LayoutFor(camera.bayer, frames.front().channels());
  return frames;
}

std::vector<LaserRate> RunLaserBenchmark(const std::vector<cv::Mat>& frames,
                                         laser::ColourLayout layout,
                                         const LaserBenchmarkOptions& options,
                                         const laser::DetectorOptions& base) {
  options.Check();
  UWS_CHECK(!frames.empty(), "bench laser: no frames");
  std::vector<LaserRate> rates;
  for (const auto method :
       {laser::Method::kArgmax, laser::Method::kCentreOfGravity, laser::Method::kThesis}) {
    laser::DetectorOptions detector = base;
    detector.method = method;
    double best = 1e30;
    size_t points = 0;
    for (int repetition = 0; repetition < options.repetitions; ++repetition) {
      points = 0;
      const auto start = std::chrono::steady_clock::now();
      for (const auto& frame : frames) {
        points += laser::DetectLaserLine(frame, layout, detector).points.size();
      }
      best = std::min(best, SecondsSince(start));
    }
    rates.push_back({laser::MethodName(method), frames.size() / best,
                     static_cast<double>(points) / frames.size()});
  }
  return rates;
}

nlohmann::json LaserBenchmarkToJson(const std::vector<LaserRate>& rates, const cv::Size& size,
                                    int frames, const std::string& source) {
  nlohmann::json json;
  json["benchmark"] = "laser";
  json["source"] = source;
  json["width"] = size.width;
  json["height"] = size.height;
  json["frames"] = frames;
  json["threads"] = 1;
  double argmax = 0.0;
  for (const auto& r : rates) {
    if (r.method == "argmax") argmax = r.frames_per_second;
  }
  for (const auto& r : rates) {
    json["results"].push_back({{"method", r.method},
                               {"frames_per_second", r.frames_per_second},
                               {"time_vs_argmax", argmax / r.frames_per_second},
                               {"mean_points_per_frame", r.mean_points}});
  }
  return json;
}

}  // namespace uwscan
