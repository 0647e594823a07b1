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
// Only earlier frames from which the scene has moved far enough across the
// line are compared with (otherwise line and texture move alike: the
// thesis's critical motion, e.g. a hover); if nearly all of a frame's line
// would go, the detector keeps it (restore). Frames before two poses are
// known (the odometry's start) are not filtered.
#pragma once

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

 private:
  struct Past {
    int frame = 0;
    double timestamp_s = 0.0;
    std::optional<Rigid3d> world_from_camera;
    std::vector<Eigen::Vector3d> points;  // candidates on the scene, camera frame
    std::vector<float> positions;         // ... and where they were (across the line)
  };
  struct Moved {
    float position, tolerance;
  };
  std::optional<Rigid3d> PredictPose(double timestamp_s) const;

  const Camera& camera_;
  MotionFilterOptions options_;
  std::deque<Past> history_;
  int frame_ = 0;
  double timestamp_s_ = 0.0;
  std::vector<int> references_;            // frames compared with
  std::vector<std::vector<Moved>> moved_;  // per scan line of the image
};

}  // namespace uwscan::laser
