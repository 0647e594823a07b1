// Accuracy of a reconstructed point cloud against the simulator's scene
// (thesis §6.4-6.5): per surface, the fit of the ideal shape (plane standard
// deviation, cylinder residual), distance errors along the surface, and the
// error of every point against its true position.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "uwscan/io/ply.h"
#include "uwscan/sensor/camera.h"
#include "uwscan/sim/scene.h"

namespace uwscan {

// A surface with fewer than kMinPoints points is counted, not measured;
// each figure below is measured only where its flag (or count) says so,
// and is 0 otherwise.
struct SurfaceAccuracy {
  static constexpr long kMinPoints = 10;
  std::string name;
  std::string type;  // plane | cylinder | hull
  long points = 0;
  bool fitted = false;     // fit_rms_m, fit_max_abs_m: the plane or cylinder fit succeeded
  double fit_rms_m = 0.0;  // std of signed distances to the fitted plane / cylinder residual
  double fit_max_abs_m = 0.0;
  // The same fit without gross outliers (mixed pixels where the line jumps
  // between a surface and what is behind it, e.g. the shaft's silhouette):
  // points farther than max(5 robust sigmas (1.4826 MAD), 5 mm) from the
  // fit are dropped and the shape refitted, twice; a cylinder's fits that
  // find them under a Cauchy loss at 5 mm (its least squares, iterative,
  // can be pulled into another minimum by a few points on the hull behind).
  // robust_fit_rms_m is of the least-squares fit to the points kept.
  bool robust_fitted = false;
  double robust_fit_rms_m = 0.0;
  long robust_outliers = 0;
  double point_error_rms_m = 0.0;        // |reconstructed - true|, from kMinPoints points
  double distance_error_mean_pct = 0.0;  // planes: |d_rec - d_true| / d_true over point pairs
  double distance_error_median_pct = 0.0;
  int distance_pairs = 0;  // the distance errors' pairs (none: not measured)
  bool Measured() const { return points >= kMinPoints; }
  nlohmann::json ToJson() const;  // null for what was not measured
};

struct CloudAccuracy {
  long points = 0;
  long matched = 0;  // with a true position on the scene (none: no point error)
  double point_error_rms_m = 0.0;
  double point_error_median_m = 0.0;
  std::vector<SurfaceAccuracy> surfaces;
  nlohmann::json ToJson() const;
  const SurfaceAccuracy* Surface(const std::string& name) const;
};

// `estimated` and `truth` hold world_from_camera per frame index; the
// cloud's world is mapped onto the true world through the first frame both
// know. Each point's pixel is recovered by projecting it into its frame with
// the estimated pose (it was triangulated on that pixel's ray), and its
// true position is the true ray of that pixel on the scene. Frames listed
// in `frame_cameras` were taken by that camera (several-camera rigs), the
// others by `camera`.
CloudAccuracy EvaluateCloud(const std::vector<CloudPoint>& cloud,
                            const std::map<int, Rigid3d>& estimated,
                            const std::map<int, Rigid3d>& truth, const Camera& camera,
                            const sim::Scene& scene,
                            const std::map<int, const Camera*>& frame_cameras = {},
                            unsigned seed = 1);

}  // namespace uwscan
