#include "uwscan/pipeline/frame_reader.h"

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <filesystem>
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
  const fs::path root = TempFolder("frame_reader");
  ReconstructJob job = SimulatedJob(root, "tank-target", ScanOptions(160, 120, 6, 3));
  std::vector<FrameRecord> frames = ReadFramesCsv(job.dataset / "frames.csv");
  ASSERT_EQ(frames.size(), 6u);
  const double step_s = 0.2;  // slower than reading such small frames, even on a busy machine
  for (size_t i = 0; i < frames.size(); ++i) frames[i].timestamp_s = 100.0 + step_s * i;
  const Rig rig = ReadRigYaml(job.dataset / "rig.yaml");
  ReconstructReport report;
  LineStage stage(job, job.dataset, rig.cameras.front(), rig.lasers.front(),
                  rig.CameraFromLaser(0, 0), frames, &report);

  const std::vector<double> live =
      DeliveryTimes(frames, &stage, std::chrono::steady_clock::now(), true);
  for (size_t i = 0; i < frames.size(); ++i) {
    EXPECT_GE(live[i], step_s * i) << "frame " << i;
    EXPECT_LT(live[i], step_s * (i + 1)) << "frame " << i;  // not a frame late
  }
  const std::vector<double> ahead =
      DeliveryTimes(frames, &stage, std::chrono::steady_clock::now(), false);
  EXPECT_LT(ahead.back(), step_s * (frames.size() - 1));
  fs::remove_all(root);
}

// Ctrl-C while a live replay waits for a frame (here 5 s away, a gap in
// the recording) stops the wait at once, as it stops a scan between frames.
TEST(FrameReader, CtrlCStopsALiveReplaysWait) {
  const fs::path root = TempFolder("frame_reader_interrupted");
  ReconstructJob job = SimulatedJob(root, "tank-target", ScanOptions(160, 120, 2, 3));
  std::vector<FrameRecord> frames = ReadFramesCsv(job.dataset / "frames.csv");
  ASSERT_EQ(frames.size(), 2u);
  frames[1].timestamp_s = frames[0].timestamp_s + 5.0;
  const Rig rig = ReadRigYaml(job.dataset / "rig.yaml");
  ReconstructReport report;
  LineStage stage(job, job.dataset, rig.cameras.front(), rig.lasers.front(),
                  rig.CameraFromLaser(0, 0), frames, &report);
  std::signal(SIGINT, SIG_DFL);  // as from a terminal
  const auto start = std::chrono::steady_clock::now();
  {
    InterruptibleScope interruptible;
    FrameReader reader(frames, &stage, nullptr, start);
    reader.Get(0);
    std::thread ctrl_c([] {
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
      std::raise(SIGINT);
    });
    EXPECT_THROW(reader.Get(1), Interrupted);
    ctrl_c.join();
  }
  EXPECT_LT(SecondsSince(start), 2.0);
  fs::remove_all(root);
}

}  // namespace
}  // namespace uwscan
