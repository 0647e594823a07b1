#include "uwscan/io/ply.h"

#include <cstring>
#include <map>
#include <sstream>

#include "uwscan/util/error.h"

namespace uwscan {
namespace {

// The vertex count is written with a fixed width and patched on Close().
constexpr int kCountWidth = 12;
constexpr const char* kCountTag = "element vertex ";

std::string Header(int64_t count) {
  char number[32];
  std::snprintf(number, sizeof(number), "%0*lld", kCountWidth, static_cast<long long>(count));
  std::ostringstream header;
  header
      << "ply\nformat binary_little_endian 1.0\ncomment uwscan point cloud, world frame, metres\n"
      << kCountTag << number << "\n"
      << "property double x\nproperty double y\nproperty double z\n"
      << "property uchar red\nproperty uchar green\nproperty uchar blue\n"
      << "property float intensity\nproperty int frame\nend_header\n";
  return header.str();
}

// One vertex record, as the header lays it out (little-endian hosts).
constexpr size_t kRecordBytes = 3 * sizeof(double) + 3 + sizeof(float) + sizeof(int32_t);

template <typename T>
char* Put(char* out, T value) {
  std::memcpy(out, &value, sizeof(T));
  return out + sizeof(T);
}

}  // namespace

PlyStreamWriter::PlyStreamWriter(std::filesystem::path path)
    : path_(path), file_(std::move(path), /*binary=*/true) {
  file_.stream() << Header(0);
}

void PlyStreamWriter::Add(const CloudPoint& p) {
  UWS_CHECK(p.position.allFinite(), path_.string(), ": refusing a non-finite point");
  // One stream write per point: eight took twice as long (BENCHMARKS.md,
  // "Unseen scans, and the PLY writer").
  char record[kRecordBytes];
  char* out = record;
  out = Put(out, p.position.x());
  out = Put(out, p.position.y());
  out = Put(out, p.position.z());
  out = Put(out, p.red);
  out = Put(out, p.green);
  out = Put(out, p.blue);
  out = Put(out, p.intensity);
  out = Put(out, p.frame);
  file_.stream().write(record, out - record);
  ++count_;
}

void PlyStreamWriter::Close() {
  std::ostream& out = file_.stream();
  out.seekp(0);
  out << Header(count_);  // same length: the count has a fixed width
  file_.Commit();
}

std::vector<CloudPoint> ReadPly(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  UWS_CHECK(in.good(), path.string(), ": cannot open");
  std::string line;
  std::getline(in, line);
  UWS_CHECK(line == "ply", path.string(), ": not a PLY file");
  int64_t count = -1;
  struct Property {
    std::string name, type;
    size_t offset;
  };
  std::vector<Property> properties;
  size_t stride = 0;
  const std::map<std::string, size_t> sizes = {{"double", 8},  {"float", 4}, {"uchar", 1},
                                               {"int", 4},     {"uint", 4},  {"float32", 4},
                                               {"float64", 8}, {"uint8", 1}, {"int32", 4}};
  bool in_vertex = false;
  while (std::getline(in, line) && line != "end_header") {
    std::istringstream words(line);
    std::string word;
    words >> word;
    if (word == "format") {
      std::string format;
      words >> format;
      UWS_CHECK(format == "binary_little_endian", path.string(),
                ": only binary_little_endian PLY is supported");
    } else if (word == "element") {
      std::string name;
      words >> name;
      in_vertex = name == "vertex";
      if (in_vertex)
        words >> count;
      else
        UWS_CHECK(count >= 0, path.string(), ": elements before 'vertex' are not supported");
    } else if (word == "property" && in_vertex) {
      Property p;
      words >> p.type >> p.name;
      const auto size = sizes.find(p.type);
      UWS_CHECK(size != sizes.end(), path.string(), ": unsupported property type '", p.type, "'");
      p.offset = stride;
      stride += size->second;
      properties.push_back(p);
    }
  }
  UWS_CHECK(count >= 0 && line == "end_header", path.string(), ": truncated header");
  std::vector<char> record(stride);
  std::vector<CloudPoint> points;
  points.reserve(count);
  const auto value = [&](const Property& p) -> double {
    const char* at = record.data() + p.offset;
    if (p.type == "double" || p.type == "float64") {
      double v;
      std::memcpy(&v, at, 8);
      return v;
    }
    if (p.type == "float" || p.type == "float32") {
      float v;
      std::memcpy(&v, at, 4);
      return v;
    }
    if (p.type == "uchar" || p.type == "uint8") return static_cast<unsigned char>(*at);
    if (p.type == "uint") {
      uint32_t v;
      std::memcpy(&v, at, 4);
      return v;
    }
    int32_t v;
    std::memcpy(&v, at, 4);
    return v;
  };
  for (int64_t i = 0; i < count; ++i) {
    in.read(record.data(), stride);
    UWS_CHECK(in.gcount() == static_cast<std::streamsize>(stride), path.string(),
              ": truncated data (", i, " of ", count, " vertices)");
    CloudPoint point;
    for (const auto& p : properties) {
      if (p.name == "x")
        point.position.x() = value(p);
      else if (p.name == "y")
        point.position.y() = value(p);
      else if (p.name == "z")
        point.position.z() = value(p);
      else if (p.name == "red")
        point.red = static_cast<uint8_t>(value(p));
      else if (p.name == "green")
        point.green = static_cast<uint8_t>(value(p));
      else if (p.name == "blue")
        point.blue = static_cast<uint8_t>(value(p));
      else if (p.name == "intensity")
        point.intensity = static_cast<float>(value(p));
      else if (p.name == "frame")
        point.frame = static_cast<int32_t>(value(p));
    }
    points.push_back(point);
  }
  return points;
}

}  // namespace uwscan
