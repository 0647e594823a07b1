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
  FrameReader(const std::vector<FrameRecord>& frames, LineStage* line_stage,
              const fusion::PoseProvider* provider,
              std::optional<std::chrono::steady_clock::time_point> live_from = std::nullopt);
  ~FrameReader();
  FrameReader(const FrameReader&) = delete;
  FrameReader& operator=(const FrameReader&) = delete;
  // Frame i with its line; the calls must ask for 0, 1, 2, ... in turn.
  ReadFrame Get(size_t i);
  // Time Get spent waiting for the reading thread.
  double seconds_waiting() const { return seconds_waiting_; }

 private:
  static constexpr size_t kAhead = 8;
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
  double seconds_waiting_ = 0.0;  // caller's thread only
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<Entry> ready_;  // read, not yet taken, in frame order
  bool stop_ = false;
  std::thread worker_;
};

}  // namespace uwscan
