// Motion-based scoring of line candidates for a laser fixed to a moving
// platform (thesis §5.5, "active features"): scene texture moves through
// the image with the platform's motion, the laser line moves only with the
// depth of the scene. A candidate peak of an earlier frame, taken for scene
// texture, is placed on the scene at the depth the frame's laser profile
// measured beside it (median over nearby scan lines), and moved into the
// current frame with the camera's motion (the current pose predicted at
// constant velocity from the last two known poses): a current candidate
// where such a moved candidate lands moves like the scene (a painted
// marking, a stripe of light on the floor) and is excluded before the
// detector picks one peak per scan line. This is the thesis's transfer of
// matched detections to a third image, with the laser's own depth for the
// matching.
//
// Where an earlier candidate can be matched with a candidate of a frame
// before it along its epipolar curve (thesis §5.5: the curve of a flat
// port, sampled over the depths the laser measures), the texture
// hypothesis is that match triangulated, not the profile's depth: a
// marking on a box beside the line, nearer than the floor the line lies
// on, is then still moved to where it is. Matches near the curve's far
// end (the line itself seen again, which stays put like a point at
// infinity) and ambiguous matches are not used.
//
// Only earlier frames from which the scene has moved far enough across the
// line are compared with (otherwise line and texture move alike: the
// thesis's critical motion, e.g. a hover); if nearly all of a frame's line
// would go, the detector keeps it (restore). Frames before two poses are
// known (the odometry's start) are not filtered.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <optional>
#include <vector>

#include "uwscan/laser/detector.h"
#include "uwscan/laser/profile.h"
#include "uwscan/sensor/camera.h"

namespace uwscan::laser {

struct MotionFilterOptions {
  bool scan_rows = true;      // as DetectorOptions::scan_rows
  double min_shift_px = 8.0;  // compare with frames the scene has moved this far from
  int max_lag_frames = 3;     // ... at most this many frames ago
  // "Moved with the scene": within this, or this share of the scene's shift
  // (pose prediction and the depth taken from the line beside it).
  double tolerance_px = 2.0;
  double tolerance_of_shift = 0.1;
  int line_search = 1;          // scan lines looked at on each side
  int depth_search_lines = 30;  // profile points within this many scan lines give the depth
  // The current pose is predicted from poses at most this many frames old.
  int max_prediction_frames = 3;
  // Epipolar matching between two earlier frames (the second at most
  // epipolar_lag_frames before the first) for the texture hypothesis.
  bool epipolar = true;
  int epipolar_lag_frames = 3;
  double epipolar_tolerance_px = 1.0;  // candidate to curve
  int epipolar_samples = 8;            // along the ray, even in inverse depth
  // Depths searched: this share of the frames' shortest laser range up to
  // this multiple of the longest.
  double near_factor = 0.5, far_factor = 2.0;
  // A match at least this far from where the curve's far end (depth x 1e4)
  // lands, so that its depth is measured, not assumed.
  double min_parallax_px = 4.0;
  void Check() const;
};

class MotionFilter {
 public:
  MotionFilter(const Camera& camera, const MotionFilterOptions& options);
  // Starts frame `frame` taken at `timestamp_s`: predicts its pose and
  // moves the candidates of the earlier frames into it.
  void Begin(int frame, double timestamp_s);
  // Whether a candidate at `position` (across the line, px) on scan line
  // `line` stands where a moved earlier candidate lands. `strict`: within
  // tolerance_px only.
  bool MovesWithScene(double position, int line, bool strict = false) const;
  // DetectorOptions::exclude_candidate for the current frame (empty when
  // nothing can be compared).
  std::function<bool(double, int)> Predicate(bool strict = false) const;
  // Remembers the current frame's candidates (all peaks) at the depths of
  // its profile.
  void End(const std::vector<LaserPoint>& candidates, const Profile& profile);
  // The pose of a frame, once known (any order; unknown frames are ignored).
  void SetPose(int frame, const Rigid3d& world_from_camera);
  // Frames compared with for the current frame (for reports and tests).
  int references() const { return static_cast<int>(references_.size()); }
  // Candidates of the frames compared with that were placed by an
  // epipolar match rather than the profile's depth (for reports and tests).
  int epipolar_matches() const { return epipolar_matches_; }
  // Candidates placed by an epipolar match so far, each counted once.
  long epipolar_matches_total() const { return epipolar_matches_total_; }

 private:
  struct Past {
    int frame = 0;
    double timestamp_s = 0.0;
    std::optional<Rigid3d> world_from_camera;
    // Every candidate: where it was, and on the scene (camera frame) at the
    // profile's depth (NaN without profile points nearby), or at its
    // epipolar match once one was found (`matched`).
    std::vector<Eigen::Vector2d> pixels;
    std::vector<std::optional<Ray>> rays;  // back-projected once
    std::vector<Eigen::Vector3d> points;
    std::vector<uint8_t> matched;
    std::vector<std::pair<int, int>> by_line;     // (scan line, index into pixels), sorted
    double min_depth_m = 0.0, max_depth_m = 0.0;  // of the profile (camera z)
    bool epipolar_done = false;
  };
  struct Moved {
    float position, tolerance;
  };
  std::optional<Rigid3d> PredictPose(double timestamp_s) const;
  // Matches `past`'s candidates along their epipolar curves with those of
  // the earliest frame with a pose within epipolar_lag_frames before it.
  void MatchEpipolar(Past* past);
  // The candidate of `earlier` on the epipolar curve of `ray` (in `past`'s
  // camera frame), triangulated (in that frame), if there is exactly one.
  std::optional<Eigen::Vector3d> MatchAlongCurve(const Ray& ray, const Rigid3d& earlier_from_past,
                                                 const Past& earlier, double near_m,
                                                 double far_m) const;

  const Camera& camera_;
  MotionFilterOptions options_;
  std::deque<Past> history_;
  int frame_ = 0;
  double timestamp_s_ = 0.0;
  std::vector<int> references_;  // frames compared with
  int epipolar_matches_ = 0;
  long epipolar_matches_total_ = 0;
  std::vector<std::vector<Moved>> moved_;  // per scan line of the image
};

}  // namespace uwscan::laser
