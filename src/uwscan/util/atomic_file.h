// Atomic file output: write to a temporary name beside the target, rename on
// success, so a crash never leaves a truncated file under the final name.
#pragma once

#include <filesystem>
#include <fstream>
#include <string>

namespace uwscan {

class AtomicFile {
 public:
  // Opens "<path>.tmp-<pid>" for writing; throws uwscan::Error naming the path.
  explicit AtomicFile(std::filesystem::path path, bool binary = false);
  ~AtomicFile();  // Removes the temporary if Commit() was not called.
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  std::ostream& stream() { return out_; }
  // Flushes, checks the stream and renames onto the final path.
  void Commit();

  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  std::filesystem::path temp_path_;
  std::ofstream out_;
  bool committed_ = false;
};

// Writes a whole string atomically.
void WriteFileAtomic(const std::filesystem::path& path, const std::string& contents);

}  // namespace uwscan
