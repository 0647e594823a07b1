// TUM trajectory files: one pose per line, "t x y z qx qy qz qw"
// (world_from_camera), '#' comments. Written with 17 significant digits so
// poses round-trip exactly.
#pragma once

#include <filesystem>
#include <memory>
#include <vector>

#include "uwscan/geometry/rigid3d.h"
#include "uwscan/util/atomic_file.h"

namespace uwscan {

struct StampedPose {
  double timestamp_s = 0.0;
  Rigid3d world_from_camera;
};

std::string TumLine(const StampedPose& pose);
// Throws uwscan::Error naming the file and line.
std::vector<StampedPose> ReadTum(const std::filesystem::path& path);
void WriteTum(const std::filesystem::path& path, const std::vector<StampedPose>& poses);
// The pose of `by_time` (timestamps not decreasing) nearest `timestamp_s`
// (the earlier of two as near), if no more than `max_dt_s` away; nullptr
// otherwise.
const StampedPose* NearestInTime(const std::vector<StampedPose>& by_time, double timestamp_s,
                                 double max_dt_s);

// Streams poses to a file, renamed into place by Commit().
class TumWriter {
 public:
  explicit TumWriter(const std::filesystem::path& path);
  void Add(const StampedPose& pose);
  void Finish() { file_.Finish(); }  // AtomicFile::Finish
  void Commit() { file_.Commit(); }

 private:
  AtomicFile file_;
};

}  // namespace uwscan
