// Reading a dataset's frames ahead of the reconstruction, on a second
// thread, with their laser lines when they need no poses.
#pragma once

#include <chrono>
#include <condition_variable>
#include <deque>
#include <exception>
#include <filesystem>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "uwscan/fusion/pose_provider.h"
#include "uwscan/io/dataset.h"
#include "uwscan/laser/detector.h"
#include "uwscan/laser/profile.h"
#include "uwscan/pipeline/line_stage.h"

namespace uwscan {

// A frame as read, with its laser line and what the pose provider made of
// it ahead.
struct ReadFrame {
  cv::Mat image;
  laser::Detection detection;
  laser::Profile profile;
  std::optional<fusion::PreparedFrame> prepared;
  // Left out of a live run that fell behind (FrameReader's max_lag_s):
  // not read, nothing else set.
  bool dropped = false;
};

// Reads (and decodes) the frames on a second thread, up to kAhead frames
// ahead of the one being processed (a live camera delivers decoded frames;
// decoding a dataset's PNGs would otherwise add to the time), and finds
// their laser lines with `line_stage` there too when the stage needs no
// poses (servo sweeps, fixed lasers without the motion filter), so that
// the two share the machine's cores; otherwise on the caller's thread,
// once the frames before have their poses. The pose provider's per-frame
// preparation (PrepareAhead: the image it tracks, the line's mask) is made
// there as well. Several frames ahead, not one: the pose estimation's time
// per frame is uneven (a keyframe's bundle adjustment takes ten frames'
// time), and with one frame ahead the reader would idle through it and
// the caller wait for the reader after it. One thread for the whole
// sequence (its decoding buffers are reused).
class FrameReader {
 public:
  // `provider` may be null (no preparation ahead).
  // The images are read by `line_stage` (LineStage::ReadFrameImage).
  // With `live_from`, no frame is read before a live camera started then
  // would have delivered it: the first at once, each later one its
  // timestamp's offset from the first's later (ReconstructJob::live).
  // With `max_lag_s` too, a frame the reader comes to more than that after
  // its delivery is dropped (ReadFrame::dropped), as a live system drops
  // the frames it cannot keep up with; never the last. Up to lag/max_lag
  // frames in a row and never more than kMaxDroppedInRow, then one read:
  // the further behind, the thinner the frames, and never a long gap for
  // the tracking to bridge (on the full tank scans, gaps of up to 15 frames
  // at 144 Hz while the start's lag was caught up put the trajectory 3 mm
  // off, ATE, against 0.7 mm with at most 3; BENCHMARKS.md, "Live: frames
  // dropped to keep up"). A machine more than four times slower than its
  // camera falls behind all the same. In an interleaved scan a laser-on
  // frame goes with the laser-off frame before it: dropped with it, since
  // its line is found against it (LineStage).
  FrameReader(const std::vector<FrameRecord>& frames, LineStage* line_stage,
              const fusion::PoseProvider* provider,
              std::optional<std::chrono::steady_clock::time_point> live_from = std::nullopt,
              std::optional<double> max_lag_s = std::nullopt);
  ~FrameReader();
  FrameReader(const FrameReader&) = delete;
  FrameReader& operator=(const FrameReader&) = delete;
  // Frame i with its line (or dropped); the calls must ask for 0, 1, 2, ...
  // in turn.
  ReadFrame Get(size_t i);
  // Time Get spent waiting for the reading thread.
  double seconds_waiting() const { return seconds_waiting_; }

 private:
  static constexpr size_t kAhead = 8;
  static constexpr int kMaxDroppedInRow = 3;
  struct Entry {
    size_t index = 0;
    ReadFrame frame;
    std::exception_ptr error;  // instead of the frame
  };
  void Work();
  ReadFrame Read(size_t i) const;
  const std::vector<FrameRecord>& frames_;
  LineStage* line_stage_;
  const bool line_ahead_;                 // found on the reading thread
  const fusion::PoseProvider* provider_;  // if it prepares frames ahead
  const std::optional<std::chrono::steady_clock::time_point> live_from_;
  const std::optional<double> max_lag_s_;
  double seconds_waiting_ = 0.0;  // caller's thread only
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<Entry> ready_;  // read, not yet taken, in frame order
  bool stop_ = false;
  std::thread worker_;
};

}  // namespace uwscan
