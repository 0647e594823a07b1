// `uwscan bench tracks`: the self-referenced odometry's feature tracks on a
// simulated dataset against the simulator's truth. The tracked image and
// line mask are the scan's own (SelfReferencedPoseProvider::PrepareAhead);
// the tracker is anchored every few frames, as at keyframes. A track's
// feature is the true scene point under its first pixel (true pose, true
// scene); its true pixel in a later frame is that point projected with that
// frame's true pose. The flow gain (tracked / true displacement since the
// track began, least squares) says whether tracks lag the motion: a bias
// of a few tenths of a per cent between the image's centre and its edges
// is enough to move a hover's rotation / translation split by per cents
// (BENCHMARKS.md, "The windowed BA on its own thread").
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>

namespace uwscan {

struct TrackAccuracyOptions {
  std::filesystem::path dataset;  // simulated: scene.yaml and groundtruth.tum
  int frames = 0;                 // 0: all
  int anchor_every = 10;          // frames between the tracker's anchors
  double contrast_scale = 0.0;    // as reconstruct --contrast-scale
  double lost_px = 2.0;           // tracks this far from the truth count as lost
  void Check() const;
};

struct TrackAccuracyResult {
  struct Gain {
    double x = 0.0, y = 0.0;                      // tracked / true displacement - 1
    double motion_x_px = 0.0, motion_y_px = 0.0;  // RMS true displacement it is measured on
    long samples = 0;
  };
  int frames = 0;
  long samples = 0;  // (track, frame) pairs after a track's first frame
  long lost = 0;     // of them, further than lost_px from the truth
  Gain all;
  Gain centre;                                       // the middle half of the image each way
  Gain edges;                                        // the rest
  double median_error_px = 0.0, p95_error_px = 0.0;  // |tracked - true|, not lost
  nlohmann::json ToJson() const;
};

// Throws uwscan::Error naming the file when the dataset is not simulated.
TrackAccuracyResult RunTrackAccuracyBenchmark(const TrackAccuracyOptions& options);

}  // namespace uwscan
