// `uwscan bench laser`: frames per second of each laser line detector on the
// same frames, in one run (ratios are what count on a noisy machine).
#pragma once

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "uwscan/laser/detector.h"

namespace uwscan {

struct LaserBenchmarkOptions {
  int width = 1280;
  int height = 960;
  int frames = 20;      // distinct synthetic frames (used when no images are given)
  int repetitions = 5;  // passes over all frames; the best pass counts
  bool bayer = false;   // synthetic frames as raw RGGB instead of 8-bit mono
  void Check() const;
};

struct LaserRate {
  std::string method;
  double frames_per_second = 0.0;
  double mean_points = 0.0;
};

// Synthetic 8-bit frames with a slanted, slightly curved laser line.
std::vector<cv::Mat> MakeLaserBenchmarkFrames(const LaserBenchmarkOptions& options);

// Up to `max_frames` frames of a dataset folder, with the layout and the
// detector settings (scan direction, laser colour) its rig implies.
std::vector<cv::Mat> LoadDatasetFrames(const std::string& dataset, int max_frames,
                                       laser::ColourLayout* layout,
                                       laser::DetectorOptions* detector);

// `base` supplies everything but the method.
std::vector<LaserRate> RunLaserBenchmark(const std::vector<cv::Mat>& frames,
                                         laser::ColourLayout layout,
                                         const LaserBenchmarkOptions& options,
                                         const laser::DetectorOptions& base = {});
nlohmann::json LaserBenchmarkToJson(const std::vector<LaserRate>& rates, const cv::Size& size,
                                    int frames, const std::string& source);

}  // namespace uwscan
