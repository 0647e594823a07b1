#include "uwscan/io/page_cache.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>

#include "uwscan/util/error.h"
#include "uwscan/util/stopwatch.h"

namespace uwscan {
namespace fs = std::filesystem;

namespace {

// Closes the descriptor on every path out.
class Descriptor {
 public:
  explicit Descriptor(const fs::path& path) : fd_(::open(path.c_str(), O_RDONLY | O_CLOEXEC)) {
    UWS_CHECK(fd_ >= 0, path.string(), ": cannot open (", std::strerror(errno), ")");
  }
  ~Descriptor() { ::close(fd_); }
  Descriptor(const Descriptor&) = delete;
  Descriptor& operator=(const Descriptor&) = delete;
  int get() const { return fd_; }

 private:
  int fd_;
};

}  // namespace

double PageCacheShare(const std::vector<fs::path>& files) {
  const long page = ::sysconf(_SC_PAGESIZE);
  std::uint64_t pages = 0, cached = 0;
  std::vector<unsigned char> resident;
  for (const fs::path& path : files) {
    const Descriptor file(path);
    const off_t size = ::lseek(file.get(), 0, SEEK_END);
    UWS_CHECK(size >= 0, path.string(), ": cannot tell its size (", std::strerror(errno), ")");
    if (size == 0) continue;
    void* map = ::mmap(nullptr, size_t(size), PROT_READ, MAP_SHARED, file.get(), 0);
    UWS_CHECK(map != MAP_FAILED, path.string(), ": cannot map (", std::strerror(errno), ")");
    const size_t n = (size_t(size) + size_t(page) - 1) / size_t(page);
    resident.assign(n, 0);
    const int status = ::mincore(map, size_t(size), resident.data());
    const int error = errno;
    ::munmap(map, size_t(size));
    UWS_CHECK(status == 0, path.string(), ": cannot query the page cache (", std::strerror(error),
              ")");
    pages += n;
    for (unsigned char r : resident) cached += r & 1u;
  }
  return pages == 0 ? 1.0 : double(cached) / double(pages);
}

FilesRead ReadFiles(const std::vector<fs::path>& files) {
  const auto start = std::chrono::steady_clock::now();
  FilesRead read;
  std::vector<char> buffer(1 << 20);
  for (const fs::path& path : files) {
    const Descriptor file(path);
    for (;;) {
      const ssize_t got = ::read(file.get(), buffer.data(), buffer.size());
      if (got < 0 && errno == EINTR) continue;
      UWS_CHECK(got >= 0, path.string(), ": read error (", std::strerror(errno), ")");
      if (got == 0) break;
      read.bytes += std::uint64_t(got);
    }
  }
  read.seconds = SecondsSince(start);
  return read;
}

}  // namespace uwscan
