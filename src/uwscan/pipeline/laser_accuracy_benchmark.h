// Laser detection accuracy on simulated `tank-target` frames with ground
// truth, for every method, turbidity and with the red LED on or off (issue
// "laser detection": RMS, completeness, outliers).
#pragma once

#include <string>
#include <vector>

#include "uwscan/eval/laser_accuracy.h"
#include "uwscan/laser/detector.h"

namespace uwscan {

struct LaserAccuracyBenchmarkOptions {
  int width = 1280;  // the thesis camera
  int height = 960;
  int frames = 6;  // servo positions spread over the sweep
  unsigned seed = 11;
  // Petzold's clear and coastal waters, two particle attenuations c_p(530)
  // between coastal and harbour (1/m), and the turbid harbour.
  std::vector<std::string> turbidities = {"clear", "coastal", "0.8", "1.6", "turbid"};
  void Check() const;
};

struct LaserAccuracyRow {
  std::string turbidity;
  bool led = true;
  std::string method;
  LaserAccuracy accuracy;
  // Triangulated detections (within 1 px of the line) against the true 3D
  // point of their scan line: RMS in metres, and how many.
  double profile_rms_m = 0.0;
  long profile_points = 0;
};

std::vector<LaserAccuracyRow> RunLaserAccuracyBenchmark(
    const LaserAccuracyBenchmarkOptions& options);
std::string LaserAccuracyToMarkdown(const std::vector<LaserAccuracyRow>& rows);

}  // namespace uwscan
