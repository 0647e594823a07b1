#include "uwscan/io/ply.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

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
    writer.Commit();
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
  writer.Commit();
  std::filesystem::resize_file(path, std::filesystem::file_size(path) - 3);
  EXPECT_THROW(ReadPly(path), Error);
  std::filesystem::remove(path);
}

// Writes `header` and then `body` (text or bytes) to a PLY in the temp folder.
std::filesystem::path WritePly(const std::string& name, const std::string& header,
                               const std::string& body) {
  const auto path = std::filesystem::temp_directory_path() / (name + ".ply");
  std::ofstream(path, std::ios::binary) << header << body;
  return path;
}

std::string ErrorOf(const std::filesystem::path& path, bool need_frame = false) {
  try {
    ReadPly(path, need_frame);
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

// As CloudCompare, MeshLab or Open3D save a cloud: ascii with normals, or
// binary with other property types; only x y z (and colour) are taken.
TEST(Ply, ReadsCloudsSavedByOtherTools) {
  const auto ascii = WritePly(
      "uwscan_ply_ascii",
      "ply\r\nformat ascii 1.0\r\ncomment saved elsewhere\r\nelement vertex 2\r\n"
      "property double x\r\nproperty double y\r\nproperty double z\r\nproperty float nx\r\n"
      "property float ny\r\nproperty float nz\r\nproperty uchar red\r\nproperty uchar green\r\n"
      "property uchar blue\r\nproperty float scalar_frame\r\nelement face 0\r\n"
      "property list uchar int vertex_indices\r\nend_header\r\n",
      "0.5 -0.25 2.125 0 0 1 10 20 30 4\r\n1e-3 2 3 0 1 0 255 0 7 5\r\n");
  const auto points = ReadPly(ascii, /*need_frame=*/true);
  ASSERT_EQ(points.size(), 2u);
  EXPECT_EQ(points[0].position, Eigen::Vector3d(0.5, -0.25, 2.125));
  EXPECT_EQ(points[1].position, Eigen::Vector3d(1e-3, 2, 3));
  EXPECT_EQ(points[0].green, 20);
  EXPECT_EQ(points[1].blue, 7);
  EXPECT_EQ(points[1].frame, 5);  // CloudCompare's name for the scalar field
  std::filesystem::remove(ascii);

  std::string body;
  const auto append = [&](const auto& value) {
    body.append(reinterpret_cast<const char*>(&value), sizeof(value));
  };
  append(int16_t{-3}), append(1.5f), append(-2.5f), append(4.0f), append(uint16_t{65535});
  const auto binary = WritePly("uwscan_ply_binary",
                               "ply\nformat binary_little_endian 1.0\nelement vertex 1\n"
                               "property short label\nproperty float x\nproperty float y\n"
                               "property float z\nproperty ushort scalar\nend_header\n",
                               body);
  const auto binary_points = ReadPly(binary);
  ASSERT_EQ(binary_points.size(), 1u);
  EXPECT_EQ(binary_points[0].position, Eigen::Vector3d(1.5, -2.5, 4.0));
  // Without the frame, a cloud cannot be evaluated against the poses.
  EXPECT_EQ(ErrorOf(binary, /*need_frame=*/true),
            binary.string() +
                ": the vertices have no 'frame' property (the frame each point was measured in)");
  std::filesystem::remove(binary);
}

TEST(Ply, ErrorsNameTheFileAndTheProblem) {
  struct Case {
    std::string header, body, expected;
  };
  const std::string start = "ply\nformat ascii 1.0\nelement vertex 1\n";
  const std::string xyz = "property float x\nproperty float y\nproperty float z\n";
  const std::vector<Case> cases = {
      {start + "property float x\nproperty float y\nend_header\n", "1 2\n",
       "the vertices have no 'z' property"},
      {start + xyz + "end_header\n", "1 nan 2\n", "vertex 0 is not finite"},
      {start + xyz + "end_header\n", "1 2\n", "vertex 0 has fewer than 3 numbers: '1 2'"},
      {start + xyz + "end_header\n", "1 2 3m\n", "vertex 0: '3m' is not a number"},
      {start + xyz + "end_header\n", "", "truncated data (0 of 1 vertices)"},
      {"ply\nformat binary_big_endian 1.0\nelement vertex 1\n" + xyz + "end_header\n", "",
       "only ascii and binary_little_endian PLY are supported, not binary_big_endian"},
      {start + "property list uchar float x\nend_header\n", "",
       "unsupported vertex property type 'list'"},
  };
  for (const auto& c : cases) {
    const auto path = WritePly("uwscan_ply_error", c.header, c.body);
    EXPECT_EQ(ErrorOf(path), path.string() + ": " + c.expected);
    std::filesystem::remove(path);
  }
}

}  // namespace
}  // namespace uwscan
