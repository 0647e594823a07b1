#include "uwscan/pipeline/frame_reader.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "uwscan/io/dataset.h"
#include "uwscan/io/rig_yaml.h"
#include "uwscan/pipeline/reconstruct.h"
#include "uwscan/pipeline/testing.h"
#include "uwscan/util/interrupt.h"
#include "uwscan/util/stopwatch.h"

namespace uwscan {
namespace {
namespace fs = std::filesystem;
using namespace pipeline_testing;

// A small simulated scan whose frames' timestamps `retime` sets, and the
// line stage a reader reads them with.
struct RetimedScan {
  RetimedScan(const std::string& name, int frame_count,
              const std::function<void(std::vector<FrameRecord>*)>& retime)
      : root(TempFolder(name)),
        job(SimulatedJob(root, "tank-target", ScanOptions(160, 120, frame_count, 3))),
        frames(ReadFramesCsv(job.dataset / "frames.csv")),
        rig(ReadRigYaml(job.dataset / "rig.yaml")) {
    retime(&frames);
    stage = std::make_unique<LineStage>(job, job.dataset, rig.cameras.front(), rig.lasers.front(),
                                        rig.CameraFromLaser(0, 0), frames, &report);
  }
  ~RetimedScan() { fs::remove_all(root); }
  fs::path root;
  ReconstructJob job;
  std::vector<FrameRecord> frames;
  Rig rig;
  ReconstructReport report;
  std::unique_ptr<LineStage> stage;
};

// When each frame of `frames` came out of a reader (seconds from `from`).
std::vector<double> DeliveryTimes(const std::vector<FrameRecord>& frames, LineStage* stage,
                                  std::chrono::steady_clock::time_point from, bool live) {
  FrameReader reader(
      frames, stage, nullptr,
      live ? std::optional<std::chrono::steady_clock::time_point>(from) : std::nullopt);
  std::vector<double> times;
  for (size_t i = 0; i < frames.size(); ++i) {
    const ReadFrame frame = reader.Get(i);
    EXPECT_FALSE(frame.image.empty());
    times.push_back(SecondsSince(from));
  }
  return times;
}

// A live replay (ReconstructJob::live) hands each frame over no sooner
// than the camera delivered it, its timestamp's offset from the first
// frame's after the start; without it the reader works ahead at once.
TEST(FrameReader, ALiveReplayDeliversEachFrameAtItsTime) {
  const double step_s = 0.2;  // slower than reading such small frames, even on a busy machine
  RetimedScan scan("frame_reader", 6, [&](std::vector<FrameRecord>* frames) {
    for (size_t i = 0; i < frames->size(); ++i) (*frames)[i].timestamp_s = 100.0 + step_s * i;
  });
  const std::vector<FrameRecord>& frames = scan.frames;
  ASSERT_EQ(frames.size(), 6u);
  const std::vector<double> live =
      DeliveryTimes(frames, scan.stage.get(), std::chrono::steady_clock::now(), true);
  for (size_t i = 0; i < frames.size(); ++i) {
    EXPECT_GE(live[i], step_s * i) << "frame " << i;
    EXPECT_LT(live[i], step_s * (i + 1)) << "frame " << i;  // not a frame late
  }
  const std::vector<double> ahead =
      DeliveryTimes(frames, scan.stage.get(), std::chrono::steady_clock::now(), false);
  EXPECT_LT(ahead.back(), step_s * (frames.size() - 1));
}

// A consumer slower than the camera: how far behind it each frame was
// taken (seconds from its delivery), or -1 where the reader dropped it.
std::vector<double> SlowConsumerLags(const std::vector<FrameRecord>& frames, LineStage* stage,
                                     double work_s, std::optional<double> max_lag_s) {
  const auto from = std::chrono::steady_clock::now();
  FrameReader reader(frames, stage, nullptr, from, max_lag_s);
  std::vector<double> lags;
  for (size_t i = 0; i < frames.size(); ++i) {
    const ReadFrame frame = reader.Get(i);
    if (frame.dropped) {
      EXPECT_TRUE(frame.image.empty()) << "frame " << i;
      lags.push_back(-1.0);
      continue;
    }
    EXPECT_FALSE(frame.image.empty()) << "frame " << i;
    lags.push_back(SecondsSince(from) - (frames[i].timestamp_s - frames.front().timestamp_s));
    std::this_thread::sleep_for(std::chrono::duration<double>(work_s));
  }
  return lags;
}

// A live replay with a maximum lag drops frames when the processing falls
// behind, as a live system slower than its camera must: here each frame
// takes three of the camera's intervals, so without drops the last frame is
// taken about 1 s late; with them no frame is taken later than the
// maximum plus the frames the reader holds ahead (kAhead = 8) and the
// one in hand, the first and the last are never dropped, and no more than
// three frames are dropped in a row (the frames thin out, no long gap).
TEST(FrameReader, ALiveReplayThatFallsBehindDropsFrames) {
  const double step_s = 0.01, work_s = 0.03, max_lag_s = 0.05;
  RetimedScan scan("frame_reader_drops", 50, [&](std::vector<FrameRecord>* frames) {
    for (size_t i = 0; i < frames->size(); ++i) (*frames)[i].timestamp_s = 7.0 + step_s * i;
  });
  ASSERT_EQ(scan.frames.size(), 50u);
  const std::vector<double> kept =
      SlowConsumerLags(scan.frames, scan.stage.get(), work_s, max_lag_s);
  const long dropped = std::count(kept.begin(), kept.end(), -1.0);
  EXPECT_GT(dropped, 10);
  EXPECT_GE(kept.front(), 0.0);
  EXPECT_GE(kept.back(), 0.0);
  const double slack_s = 0.15;  // a busy test machine's sleeps and wake-ups
  for (size_t i = 0; i < kept.size(); ++i)
    EXPECT_LT(kept[i], max_lag_s + 9 * work_s + slack_s) << "frame " << i;
  int run = 0, longest_run = 0;
  for (double lag : kept) {
    run = lag < 0 ? run + 1 : 0;
    longest_run = std::max(longest_run, run);
  }
  EXPECT_LE(longest_run, 3);
  EXPECT_GE(longest_run, 2);  // as far behind as it is, more than every other one

  const std::vector<double> all =
      SlowConsumerLags(scan.frames, scan.stage.get(), work_s, std::nullopt);
  EXPECT_EQ(std::count(all.begin(), all.end(), -1.0), 0);
  EXPECT_GT(all.back(), 0.8);  // 50 x 30 ms of work for 0.49 s of frames
}

// In an interleaved scan (frames.csv laser_on) a laser-on frame is kept
// only with the laser-off frame before it, against which its line is found.
TEST(FrameReader, ALiveReplayDropsAnInterleavedScansFramesInPairs) {
  RetimedScan scan("frame_reader_pairs", 50, [](std::vector<FrameRecord>* frames) {
    for (size_t i = 0; i < frames->size(); ++i) {
      (*frames)[i].timestamp_s = 7.0 + 0.01 * i;
      (*frames)[i].laser_on = i % 2 == 1;
    }
  });
  ASSERT_EQ(scan.frames.size(), 50u);
  const std::vector<double> kept = SlowConsumerLags(scan.frames, scan.stage.get(), 0.03, 0.05);
  EXPECT_GT(std::count(kept.begin(), kept.end(), -1.0), 10);
  for (size_t i = 1; i + 1 < kept.size(); i += 2) {
    if (kept[i] >= 0) {
      EXPECT_GE(kept[i - 1], 0.0) << "laser-on frame " << i;
    }
  }
}

// Ctrl-C while a live replay waits for a frame (here 5 s away, a gap in
// the recording) stops the wait at once, as it stops a scan between frames.
TEST(FrameReader, CtrlCStopsALiveReplaysWait) {
  RetimedScan scan("frame_reader_interrupted", 2, [](std::vector<FrameRecord>* frames) {
    if (frames->size() == 2) (*frames)[1].timestamp_s = (*frames)[0].timestamp_s + 5.0;
  });
  ASSERT_EQ(scan.frames.size(), 2u);
  std::signal(SIGINT, SIG_DFL);  // as from a terminal
  const auto start = std::chrono::steady_clock::now();
  {
    InterruptibleScope interruptible;
    FrameReader reader(scan.frames, scan.stage.get(), nullptr, start);
    reader.Get(0);
    std::thread ctrl_c([] {
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
      std::raise(SIGINT);
    });
    EXPECT_THROW(reader.Get(1), Interrupted);
    ctrl_c.join();
  }
  EXPECT_LT(SecondsSince(start), 2.0);
}

}  // namespace
}  // namespace uwscan
