#include "uwscan/pipeline/frame_reader.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

#include "uwscan/util/error.h"
#include "uwscan/util/interrupt.h"
#include "uwscan/util/stopwatch.h"

namespace uwscan {

FrameReader::FrameReader(const std::vector<FrameRecord>& frames, LineStage* line_stage,
                         const fusion::PoseProvider* provider,
                         std::optional<std::chrono::steady_clock::time_point> live_from,
                         std::optional<double> max_lag_s)
    : frames_(frames),
      line_stage_(line_stage),
      line_ahead_(!line_stage->NeedsPoses()),
      provider_(provider && provider->PreparesAhead() ? provider : nullptr),
      live_from_(live_from),
      max_lag_s_(max_lag_s) {
  UWS_CHECK(!max_lag_s || (live_from && *max_lag_s > 0.0),
            "frame reader: a maximum lag needs a live replay and must be > 0");
  if (!frames_.empty()) worker_ = std::thread([this] { Work(); });
}

FrameReader::~FrameReader() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  changed_.notify_all();
  if (worker_.joinable()) worker_.join();
}

ReadFrame FrameReader::Get(size_t i) {
  const auto start = std::chrono::steady_clock::now();
  std::unique_lock<std::mutex> lock(mutex_);
  // A live replay may wait long for a frame (a gap in the recording):
  // Ctrl-C is heard meanwhile.
  while (
      !changed_.wait_for(lock, std::chrono::milliseconds(50), [this] { return !ready_.empty(); })) {
    ThrowIfInterrupted();
  }
  seconds_waiting_ += SecondsSince(start);
  Entry entry = std::move(ready_.front());
  ready_.pop_front();
  lock.unlock();
  changed_.notify_all();
  if (entry.error) std::rethrow_exception(entry.error);  // a read error, named
  UWS_CHECK(entry.index == i, "frame reader: frame ", i, " asked for out of turn");
  if (!line_ahead_ && !entry.frame.dropped) {
    line_stage_->Process(i, entry.frame.image, &entry.frame.detection, &entry.frame.profile);
  }
  return std::move(entry.frame);
}

void FrameReader::Work() {
  int dropped_in_row = 0;
  for (size_t i = 0; i < frames_.size(); ++i) {
    bool drop = false;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      changed_.wait(lock, [this] { return stop_ || ready_.size() < kAhead; });
      if (live_from_) {
        const std::chrono::duration<double> offset(frames_[i].timestamp_s -
                                                   frames_.front().timestamp_s);
        const auto due =
            *live_from_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(offset);
        changed_.wait_until(lock, due, [this] { return stop_; });
        if (max_lag_s_ && i + 1 < frames_.size()) {
          const double lag_s =
              std::chrono::duration<double>(std::chrono::steady_clock::now() - due).count();
          drop =
              lag_s > *max_lag_s_ &&
              dropped_in_row < std::min<double>(kMaxDroppedInRow, std::floor(lag_s / *max_lag_s_));
        }
      }
      if (stop_) return;
    }
    // Interleaved scans: a laser-on frame's line is found against the
    // laser-off frame before it (LineStage), so the two go together.
    if (dropped_in_row > 0 && i + 1 < frames_.size() && frames_[i - 1].LaserOff() &&
        frames_[i].laser_on.value_or(false))
      drop = true;
    dropped_in_row = drop ? dropped_in_row + 1 : 0;
    Entry entry{i, {}, nullptr};
    try {
      if (drop)
        entry.frame.dropped = true;
      else
        entry.frame = Read(i);
    } catch (...) {
      entry.error = std::current_exception();
    }
    const bool failed = entry.error != nullptr;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ready_.push_back(std::move(entry));
    }
    changed_.notify_all();
    if (failed) return;  // the caller stops at this frame
  }
}

ReadFrame FrameReader::Read(size_t i) const {
  ReadFrame frame;
  frame.image = line_stage_->ReadFrameImage(i);
  if (line_ahead_) line_stage_->Process(i, frame.image, &frame.detection, &frame.profile);
  if (provider_) {
    frame.prepared = provider_->PrepareAhead({frames_[i].index, frames_[i].timestamp_s, frame.image,
                                              line_ahead_ ? &frame.detection : nullptr});
  }
  return frame;
}

}  // namespace uwscan
