// Whether files are in the operating system's page cache, and reading them
// into it. A dataset read from a cold disk can be slower than the camera
// that recorded it; `uwscan bench pipeline` uses these to time the
// processing apart from the disk, and says how fast the disk delivered.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

namespace uwscan {

// Share of the files' bytes held in the page cache now (Linux mincore),
// 0..1; 1 for no bytes. Throws naming the file it cannot open or map.
double PageCacheShare(const std::vector<std::filesystem::path>& files);

struct FilesRead {
  std::uint64_t bytes = 0;
  double seconds = 0.0;
};

// Reads every file once, to the end (so into the page cache). Throws
// naming the file it cannot read.
FilesRead ReadFiles(const std::vector<std::filesystem::path>& files);

}  // namespace uwscan
