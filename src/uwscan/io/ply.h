// Binary little-endian PLY point clouds, the format CloudCompare, MeshLab and
// Open3D open directly. Per vertex: x y z (float64), red green blue (uint8),
// intensity (float32), frame (int32).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "uwscan/util/atomic_file.h"

namespace uwscan {

struct CloudPoint {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  uint8_t red = 255, green = 255, blue = 255;
  float intensity = 0.0f;
  int32_t frame = 0;
};

// Streams points to disk as they come (bounded memory). The file appears
// under its final name only after Commit(); without Commit() the temporary
// is removed (AtomicFile).
class PlyStreamWriter {
 public:
  explicit PlyStreamWriter(std::filesystem::path path);
  PlyStreamWriter(const PlyStreamWriter&) = delete;
  PlyStreamWriter& operator=(const PlyStreamWriter&) = delete;

  void Add(const CloudPoint& point);
  // Completes the file under its temporary name (AtomicFile::Finish).
  void Finish();
  void Commit();  // finishes (if not done yet) and renames into place
  int64_t count() const { return count_; }

 private:
  std::filesystem::path path_;
  AtomicFile file_;  // the header's vertex count is patched in place on Finish()
  int64_t count_ = 0;
  bool finished_ = false;
};

// Reads the vertices of a PLY written by PlyStreamWriter or by another tool
// (ascii or binary little-endian, scalar properties, x y z required, and
// frame too with `need_frame`; red, green, blue, intensity and frame read
// where present (CloudCompare's scalar_intensity and scalar_frame too),
// others skipped). Throws uwscan::Error naming the file for anything else,
// a truncated file or a non-finite vertex.
std::vector<CloudPoint> ReadPly(const std::filesystem::path& path, bool need_frame = false);

}  // namespace uwscan
