#include "uwscan/io/page_cache.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <string>

#include "uwscan/util/error.h"

namespace uwscan {
namespace {

namespace fs = std::filesystem;

class PageCacheTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("uwscan_page_cache_" + std::to_string(getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path Write(const std::string& name, size_t bytes) {
    const fs::path path = dir_ / name;
    std::ofstream(path, std::ios::binary) << std::string(bytes, 'x');
    return path;
  }
  // Asks the kernel to drop the file's clean pages; false if it kept any.
  static bool Evict(const fs::path& path) {
    const int fd = ::open(path.c_str(), O_RDONLY);
    if (fd < 0) return false;
    ::fdatasync(fd);
    const bool asked = ::posix_fadvise(fd, 0, 0, POSIX_FADV_DONTNEED) == 0;
    ::close(fd);
    return asked && PageCacheShare({path}) == 0.0;
  }
  fs::path dir_;
};

TEST_F(PageCacheTest, ReadingBringsFilesIntoTheCache) {
  const std::vector<fs::path> files = {Write("a.bin", 300000), Write("b.bin", 5000),
                                       Write("empty.bin", 0)};
  const bool evicted = Evict(files[0]) && Evict(files[1]);  // (the empty file has no pages)
  const FilesRead read = ReadFiles(files);
  EXPECT_EQ(read.bytes, 305000u);
  EXPECT_GE(read.seconds, 0.0);
  EXPECT_EQ(PageCacheShare(files), 1.0);
  if (!evicted) GTEST_SKIP() << "this file system keeps pages posix_fadvise asks to drop";
  EXPECT_TRUE(Evict(files[0]));
  // b.bin's 2 pages of 4 KiB are still cached, a.bin's 74 are not.
  const double share = PageCacheShare(files);
  EXPECT_GT(share, 0.0);
  EXPECT_LT(share, 0.1);
}

TEST_F(PageCacheTest, NoFilesAreAllCached) { EXPECT_EQ(PageCacheShare({}), 1.0); }

TEST_F(PageCacheTest, AMissingFileIsNamed) {
  const fs::path missing = dir_ / "missing.png";
  try {
    ReadFiles({missing});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("missing.png: cannot open"), std::string::npos);
  }
  EXPECT_THROW(PageCacheShare({missing}), Error);
}

}  // namespace
}  // namespace uwscan
