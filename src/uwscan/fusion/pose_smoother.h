// Streaming trajectory smoothing with bounded delay: a vehicle's motion is
// band-limited (a hovering ROV moves at about 1 Hz) while the camera runs at
// 144 Hz, so per-frame pose noise can be averaged out without bending the
// motion. Each pose is replaced by the value at its time of a quadratic
// least-squares fit (Savitzky-Golay) to the poses within `half_window`
// frames on each side (translation directly, rotation as rotation vectors
// relative to the frame's own rotation). Poses come out `half_window`
// frames late; a gap (Flush) ends a segment, which is never smoothed across.
#pragma once

#include <deque>
#include <vector>

#include "uwscan/fusion/pose_provider.h"

namespace uwscan::fusion {

class PoseSmoother {
 public:
  explicit PoseSmoother(int half_window) : half_window_(half_window) {}
  // Adds a raw pose; returns the smoothed poses that are now final.
  std::vector<PoseUpdate> Add(const PoseUpdate& pose, double timestamp_s);
  // Ends the segment: smooths and returns every pose still held.
  std::vector<PoseUpdate> Flush();

 private:
  PoseUpdate Smooth(size_t index) const;
  struct Entry {
    PoseUpdate pose;
    double timestamp_s;
  };
  int half_window_;
  std::deque<Entry> buffer_;
  size_t emitted_ = 0;  // entries at the front already returned
};

}  // namespace uwscan::fusion
