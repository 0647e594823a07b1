#include "uwscan/io/ply.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "uwscan/util/error.h"

namespace uwscan {
namespace {

TEST(Ply, StreamedCloudReadsBack) {
  const auto path = std::filesystem::temp_directory_path() / "uwscan_ply_test.ply";
  {
    PlyStreamWriter writer(path);
    for (int i = 0; i < 1000; ++i) {
      CloudPoint p;
      p.position = Eigen::Vector3d(i * 0.001, -i * 1e-7, 2.0 + 1.0 / 3.0);
      p.red = static_cast<uint8_t>(i % 256);
      p.intensity = i * 0.5f;
      p.frame = i / 10;
      writer.Add(p);
    }
    EXPECT_FALSE(std::filesystem::exists(path));  // not under the final name yet
    writer.Close();
  }
  const auto points = ReadPly(path);
  ASSERT_EQ(points.size(), 1000u);
  EXPECT_EQ(points[999].position, Eigen::Vector3d(999 * 0.001, -999 * 1e-7, 2.0 + 1.0 / 3.0));
  EXPECT_EQ(points[300].red, 300 % 256);
  EXPECT_EQ(points[300].intensity, 150.0f);
  EXPECT_EQ(points[999].frame, 99);
  std::filesystem::remove(path);
}

TEST(Ply, UnclosedWriterLeavesNothing) {
  const auto path = std::filesystem::temp_directory_path() / "uwscan_ply_unclosed.ply";
  {
    PlyStreamWriter writer(path);
    writer.Add(CloudPoint{});
  }
  EXPECT_FALSE(std::filesystem::exists(path));
  for (const auto& entry :
       std::filesystem::directory_iterator(std::filesystem::temp_directory_path())) {
    EXPECT_EQ(entry.path().filename().string().find("uwscan_ply_unclosed.ply.tmp"),
              std::string::npos);
  }
}

TEST(Ply, RejectsNaNAndTruncation) {
  const auto path = std::filesystem::temp_directory_path() / "uwscan_ply_bad.ply";
  PlyStreamWriter writer(path);
  CloudPoint bad;
  bad.position.x() = std::nan("");
  EXPECT_THROW(writer.Add(bad), Error);
  writer.Add(CloudPoint{});
  writer.Close();
  std::filesystem::resize_file(path, std::filesystem::file_size(path) - 3);
  EXPECT_THROW(ReadPly(path), Error);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace uwscan
