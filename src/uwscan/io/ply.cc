#include "uwscan/io/ply.h"

#include <algorithm>
#include <charconv>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <tuple>

#include "uwscan/util/error.h"

namespace uwscan {
namespace {

// The vertex count is written with a fixed width and patched on Finish().
constexpr int kCountWidth = 12;
constexpr const char* kCountTag = "element vertex ";

std::string PlyHeader(int64_t count) {
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
  file_.stream() << PlyHeader(0);
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

void PlyStreamWriter::Finish() {
  if (finished_) return;
  std::ostream& out = file_.stream();
  out.seekp(0);
  out << PlyHeader(count_);  // same length: the count has a fixed width
  file_.Finish();
  finished_ = true;
}

void PlyStreamWriter::Commit() {
  Finish();
  file_.Commit();
}

namespace {

// A scalar vertex property: where it sits in a binary record and how to read it.
struct PlyProperty {
  std::string name, type;
  size_t offset = 0, size = 0;
  bool is_float = false, is_signed = false;
};

// PLY's scalar types (both spellings) -> size, floating point, signed.
bool DescribePlyType(const std::string& type, PlyProperty* p) {
  static const std::map<std::string, std::tuple<size_t, bool, bool>> kTypes = {
      {"char", {1, false, true}},    {"int8", {1, false, true}},    {"uchar", {1, false, false}},
      {"uint8", {1, false, false}},  {"short", {2, false, true}},   {"int16", {2, false, true}},
      {"ushort", {2, false, false}}, {"uint16", {2, false, false}}, {"int", {4, false, true}},
      {"int32", {4, false, true}},   {"uint", {4, false, false}},   {"uint32", {4, false, false}},
      {"float", {4, true, true}},    {"float32", {4, true, true}},  {"double", {8, true, true}},
      {"float64", {8, true, true}}};
  const auto found = kTypes.find(type);
  if (found == kTypes.end()) return false;
  std::tie(p->size, p->is_float, p->is_signed) = found->second;
  return true;
}

// A little-endian binary value of `p` at `at`.
double BinaryValue(const PlyProperty& p, const char* at) {
  if (p.is_float) {
    if (p.size == 8) {
      double v;
      std::memcpy(&v, at, 8);
      return v;
    }
    float v;
    std::memcpy(&v, at, 4);
    return v;
  }
  uint32_t bits = 0;
  std::memcpy(&bits, at, p.size);
  if (!p.is_signed) return bits;
  const int shift = 32 - 8 * static_cast<int>(p.size);  // sign-extend from p.size bytes
  return static_cast<int32_t>(bits << shift) >> shift;
}

}  // namespace

std::vector<CloudPoint> ReadPly(const std::filesystem::path& path, bool need_frame) {
  std::ifstream in(path, std::ios::binary);
  UWS_CHECK(in.good(), path.string(), ": cannot open");
  std::string line;
  std::getline(in, line);
  UWS_CHECK(line == "ply" || line == "ply\r", path.string(), ": not a PLY file");
  int64_t count = -1;
  bool ascii = false;
  std::vector<PlyProperty> properties;
  size_t stride = 0;
  bool in_vertex = false;
  while (std::getline(in, line) && line != "end_header" && line != "end_header\r") {
    std::istringstream words(line);
    std::string word;
    words >> word;
    if (word == "format") {
      std::string format;
      words >> format;
      UWS_CHECK(format == "binary_little_endian" || format == "ascii", path.string(),
                ": only ascii and binary_little_endian PLY are supported, not ", format);
      ascii = format == "ascii";
    } else if (word == "element") {
      std::string name;
      words >> name;
      in_vertex = name == "vertex";
      if (in_vertex)
        words >> count;
      else
        UWS_CHECK(count >= 0, path.string(), ": elements before 'vertex' are not supported");
    } else if (word == "property" && in_vertex) {
      PlyProperty p;
      words >> p.type >> p.name;
      // CloudCompare saves a scalar field NAME as scalar_NAME.
      if (p.name == "scalar_frame" || p.name == "scalar_intensity") p.name.erase(0, 7);
      UWS_CHECK(DescribePlyType(p.type, &p), path.string(), ": unsupported vertex property type '",
                p.type, "'");
      p.offset = stride;
      stride += p.size;
      properties.push_back(p);
    }
  }
  UWS_CHECK(count >= 0 && (line == "end_header" || line == "end_header\r"), path.string(),
            ": truncated header");
  std::vector<const char*> needed = {"x", "y", "z"};
  if (need_frame) needed.push_back("frame");
  for (const char* name : needed) {
    UWS_CHECK(std::any_of(properties.begin(), properties.end(),
                          [&](const PlyProperty& p) { return p.name == name; }),
              path.string(), ": the vertices have no '", name, "' property",
              std::string(name) == "frame" ? " (the frame each point was measured in)" : "");
  }
  std::vector<char> record(stride);
  std::vector<double> values(properties.size());
  std::vector<CloudPoint> points;
  points.reserve(count);
  for (int64_t i = 0; i < count; ++i) {
    if (ascii) {
      UWS_CHECK(static_cast<bool>(std::getline(in, line)), path.string(), ": truncated data (", i,
                " of ", count, " vertices)");
      std::istringstream words(line);
      std::string word;
      for (double& v : values) {
        UWS_CHECK(static_cast<bool>(words >> word), path.string(), ": vertex ", i,
                  " has fewer than ", values.size(), " numbers: '", line, "'");
        const auto parsed = std::from_chars(word.data(), word.data() + word.size(), v);
        UWS_CHECK(parsed.ec == std::errc() && parsed.ptr == word.data() + word.size(),
                  path.string(), ": vertex ", i, ": '", word, "' is not a number");
      }
    } else {
      in.read(record.data(), stride);
      UWS_CHECK(in.gcount() == static_cast<std::streamsize>(stride), path.string(),
                ": truncated data (", i, " of ", count, " vertices)");
      for (size_t k = 0; k < properties.size(); ++k)
        values[k] = BinaryValue(properties[k], record.data() + properties[k].offset);
    }
    CloudPoint point;
    for (size_t k = 0; k < properties.size(); ++k) {
      const std::string& name = properties[k].name;
      const double v = values[k];
      if (name == "x")
        point.position.x() = v;
      else if (name == "y")
        point.position.y() = v;
      else if (name == "z")
        point.position.z() = v;
      else if (name == "red")
        point.red = static_cast<uint8_t>(v);
      else if (name == "green")
        point.green = static_cast<uint8_t>(v);
      else if (name == "blue")
        point.blue = static_cast<uint8_t>(v);
      else if (name == "intensity")
        point.intensity = static_cast<float>(v);
      else if (name == "frame")
        point.frame = static_cast<int32_t>(v);
    }
    UWS_CHECK(point.position.allFinite(), path.string(), ": vertex ", i, " is not finite");
    points.push_back(point);
  }
  return points;
}

}  // namespace uwscan
