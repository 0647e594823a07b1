// Dataset folder (architecture.md): rig.yaml, frames.csv
// (index,timestamp_s,file[,laser_angle_rad][,laser_on]), frames/, groundtruth.tum,
// scene.yaml, laser_gt.csv, calib/{air,water,laser}/. Writers stream, so
// memory stays flat with sequence length.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "uwscan/util/atomic_file.h"

namespace uwscan {

struct FrameRecord {
  int index = 0;
  double timestamp_s = 0.0;
  std::string file;                       // relative to the dataset folder
  std::optional<double> laser_angle_rad;  // servo angle of the first laser
  // Lasers switched on in this frame; unset = always on. Interleaved scans
  // (thesis §5.4/5.5) alternate on and off frames.
  std::optional<bool> laser_on;
  bool LaserOff() const { return laser_on && !*laser_on; }
};

// File name of frame `index` inside the dataset: frames/000123.png.
std::string FrameFileName(int index);

std::vector<FrameRecord> ReadFramesCsv(const std::filesystem::path& path);

// Mean time between frames (s); 0 for fewer than two frames.
double MeanFrameInterval(const std::vector<FrameRecord>& frames);

// Frames a camera or its recorder dropped: each step between consecutive
// timestamps longer than 1.5 times the median step is a gap, of
// round(step / median) - 1 missing frames (at least one).
struct FrameGaps {
  int gaps = 0;
  int missing = 0;
  double longest_s = 0.0;      // the longest such step
  double median_step_s = 0.0;  // the frame period (0: fewer than three frames)
};
FrameGaps FindFrameGaps(const std::vector<FrameRecord>& frames);

// A line-laser scan takes tens of frames a second. Frames a median of more
// than kSlowFrameStepS apart are more likely a camera's milliseconds read as
// seconds (the odometry's choices by frame rate and the real-time factor
// follow the timestamps); a warning naming `csv` then, "" otherwise.
constexpr double kSlowFrameStepS = 1.0;
std::string SlowFramesWarning(const FrameGaps& gaps, const std::string& csv);

class FramesCsvWriter {
 public:
  FramesCsvWriter(const std::filesystem::path& path, bool with_laser_angle,
                  bool with_laser_on = false);
  void Add(const FrameRecord& record);
  void Commit() { file_.Commit(); }

 private:
  AtomicFile file_;
  bool with_laser_angle_;
  bool with_laser_on_;
};

// laser_gt.csv: frame,laser,u,v,x,y,z (camera frame, metres).
struct LaserTruthRow {
  int frame = 0, laser = 0;
  double u = 0, v = 0, x = 0, y = 0, z = 0;
};

class LaserTruthWriter {
 public:
  explicit LaserTruthWriter(const std::filesystem::path& path);
  void Add(const LaserTruthRow& row);
  void Commit() { file_.Commit(); }

 private:
  AtomicFile file_;
};

std::vector<LaserTruthRow> ReadLaserTruthCsv(const std::filesystem::path& path);

}  // namespace uwscan
