#include "uwscan/pipeline/vo_dataset.h"

#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "uwscan/io/image.h"
#include "uwscan/io/rig_yaml.h"
#include "uwscan/util/atomic_file.h"
#include "uwscan/util/error.h"

namespace uwscan {
namespace {

std::vector<std::string> SplitCsvLine(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream in(line);
  std::string field;
  while (std::getline(in, field, ',')) {
    const size_t a = field.find_first_not_of(" \t\r"), b = field.find_last_not_of(" \t\r");
    fields.push_back(a == std::string::npos ? "" : field.substr(a, b - a + 1));
  }
  return fields;
}

double ParseNumber(const std::string& text, const std::string& where) {
  size_t used = 0;
  double value = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  UWS_CHECK(used == text.size() && !text.empty(), where, ": '", text, "' is not a number");
  return value;
}

}  // namespace

std::vector<VoFrameEntry> ParseFramesCsv(const std::string& text, const std::string& source) {
  std::istringstream in(text);
  std::string line;
  UWS_CHECK(std::getline(in, line), source, ": empty file, expected a header line");
  const std::vector<std::string> header = SplitCsvLine(line);
  UWS_CHECK(header.size() >= 3 && header[0] == "index" && header[1] == "timestamp_s" &&
                header[2] == "file" &&
                (header.size() == 3 || (header.size() == 4 && header[3] == "laser_angle_rad")),
            source, ":1: header must be index,timestamp_s,file[,laser_angle_rad]");
  std::vector<VoFrameEntry> frames;
  int line_number = 1;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::string where = source + ":" + std::to_string(line_number);
    const std::vector<std::string> fields = SplitCsvLine(line);
    UWS_CHECK(fields.size() == header.size(), where, ": expected ", header.size(), " fields, got ",
              fields.size());
    VoFrameEntry frame;
    frame.index = int(ParseNumber(fields[0], where));
    frame.timestamp_s = ParseNumber(fields[1], where);
    frame.file = fields[2];
    UWS_CHECK(!frame.file.empty(), where, ": empty file name");
    if (fields.size() == 4) frame.laser_angle_rad = ParseNumber(fields[3], where);
    UWS_CHECK(frames.empty() || frame.timestamp_s > frames.back().timestamp_s, where,
              ": timestamps must increase");
    frames.push_back(frame);
  }
  return frames;
}

VoDataset ReadVoDataset(const std::filesystem::path& dir) {
  UWS_CHECK(std::filesystem::is_directory(dir), dir.string(), ": not a dataset folder");
  VoDataset dataset;
  dataset.dir = dir;
  dataset.rig = ReadRigYaml(dir / "rig.yaml");
  const std::filesystem::path frames_csv = dir / "frames.csv";
  std::ifstream in(frames_csv);
  UWS_CHECK(in, frames_csv.string(), ": cannot open");
  std::stringstream buffer;
  buffer << in.rdbuf();
  dataset.frames = ParseFramesCsv(buffer.str(), frames_csv.string());
  UWS_CHECK(!dataset.frames.empty(), frames_csv.string(), ": no frames");
  if (std::filesystem::exists(dir / "groundtruth.tum")) {
    dataset.ground_truth = ReadTumTrajectory(dir / "groundtruth.tum");
  }
  return dataset;
}

cv::Mat ReadFrameImage(const VoDataset& dataset, const VoFrameEntry& frame) {
  const std::filesystem::path path = dataset.dir / frame.file;
  if (!std::filesystem::exists(path)) return cv::Mat();
  return cv::imread(path.string(), cv::IMREAD_UNCHANGED);
}

cv::Mat TrackingImage(const cv::Mat& raw, const std::string& bayer) {
  if (raw.empty()) return raw;
  if (raw.channels() == 1 && bayer != "none") {
    cv::Mat green;
    cv::extractChannel(DemosaicToBgr(raw, bayer), green, 1);
    return green;
  }
  if (raw.channels() == 3 || raw.channels() == 4) {
    cv::Mat green;
    cv::extractChannel(raw, green, 1);
    return green;
  }
  return raw;
}

void WriteFramesCsv(const std::filesystem::path& path, const std::vector<VoFrameEntry>& frames) {
  bool angles = !frames.empty() && frames.front().laser_angle_rad.has_value();
  std::ostringstream out;
  out.precision(17);
  out << "index,timestamp_s,file" << (angles ? ",laser_angle_rad" : "") << "\n";
  for (const VoFrameEntry& f : frames) {
    out << f.index << "," << f.timestamp_s << "," << f.file;
    if (angles) out << "," << f.laser_angle_rad.value_or(0.0);
    out << "\n";
  }
  WriteFileAtomic(path, out.str());
}

}  // namespace uwscan
