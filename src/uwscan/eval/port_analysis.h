// How wrong is a pinhole model for a flat-port camera? (thesis §4.2,
// Figs. 4.10-4.12, Tab. 4.6, eq. 4.27)
#pragma once

#include <vector>

#include "uwscan/sensor/camera.h"

namespace uwscan {

struct PinholeFitOptions {
  double depth_m = 3.0;  // fit on the virtual plane z = depth (thesis: 3 m)
  int grid_step_px = 20;
  void Check() const;
};

struct ErrorStats {
  double max_px = 0.0;
  double median_px = 0.0;
  double p95_px = 0.0;
  double rms_px = 0.0;
  int count = 0;
};
ErrorStats ComputeErrorStats(std::vector<double> errors);

struct PinholeFit {
  Camera pinhole;     // model: pinhole, same size, fitted intrinsics and distortion
  ErrorStats at_fit;  // residuals on the fitting plane
  int iterations = 0;
};

// Best pinhole + Brown approximation of a flat-port camera: minimises the
// re-projection error of points on the plane z = depth seen through the
// port, over the whole image.
PinholeFit FitPinholeToFlatPort(const Camera& flatport, const PinholeFitOptions& options);

// Error of `pinhole` against the flat-port camera for points on the plane
// z = depth (the thesis's pinhole model error maps, as statistics).
ErrorStats PinholeErrorAtDepth(const Camera& flatport, const Camera& pinhole, double depth_m,
                               int grid_step_px = 20);

// d_air that cancels refraction for the air ray of slope angle alpha (eq. 4.27).
double OptimalAirGap(const FlatPort& port, double air_angle_rad);

}  // namespace uwscan
