// A line laser behind its own flat port (thesis §4.3, §6.2): the light sheet
// of the bare laser (its x-z plane) is refracted by the glass; if the port
// is tilted about the line direction the sheet bends into a cone-like
// surface. The simulator represents it by the projector model of eq. 4.30
// (pose + bend p1) fitted by least squares to exactly refracted sheet rays,
// so rendering, laser_gt.csv and rig.yaml use one consistent sheet.
#pragma once

#include "uwscan/geometry/rigid3d.h"
#include "uwscan/sensor/camera.h"

namespace uwscan::sim {

struct LaserPortFit {
  Rigid3d inner_from_model;  // model laser frame in the bare laser's frame
  double p1 = 0.0;
  double rms_m = 0.0;  // rms distance of the refracted sheet points from the model
  double max_m = 0.0;
};

// `port` in the bare laser's frame (normal pointing into the water), fan
// `fan_angle_rad`, fitted over ranges [min_range_m, max_range_m] from the
// port. Throws uwscan::Error if the sheet cannot be refracted.
LaserPortFit FitLaserBehindPort(const FlatPort& port, double fan_angle_rad, double min_range_m,
                                double max_range_m);

}  // namespace uwscan::sim
