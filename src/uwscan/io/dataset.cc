#include "uwscan/io/dataset.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "uwscan/io/timestamps.h"
#include "uwscan/util/csv.h"
#include "uwscan/util/error.h"
#include "uwscan/util/statistics.h"

namespace uwscan {

std::string FrameFileName(int index) { return fmt::format("frames/{:06d}.png", index); }

double MeanFrameInterval(const std::vector<FrameRecord>& frames) {
  if (frames.size() < 2) return 0.0;
  return (frames.back().timestamp_s - frames.front().timestamp_s) / (frames.size() - 1);
}

FrameGaps FindFrameGaps(const std::vector<FrameRecord>& frames) {
  FrameGaps found;
  if (frames.size() < 3) return found;
  std::vector<double> steps;
  for (size_t i = 1; i < frames.size(); ++i)
    steps.push_back(frames[i].timestamp_s - frames[i - 1].timestamp_s);
  const double median = Median(steps);
  if (!(median > 0)) return found;
  found.median_step_s = median;
  for (double step : steps) {
    if (!(step > 1.5 * median)) continue;
    ++found.gaps;
    found.missing += std::max(1, static_cast<int>(std::lround(step / median)) - 1);
    found.longest_s = std::max(found.longest_s, step);
  }
  return found;
}

std::string SlowFramesWarning(const FrameGaps& gaps, const std::string& csv) {
  if (!(gaps.median_step_s > kSlowFrameStepS)) return "";
  return fmt::format(
      "{}: the frames are {:.4g} s apart (median): {:.3g} frames a second; if timestamp_s is in "
      "milliseconds, divide it by 1000",
      csv, gaps.median_step_s, 1.0 / gaps.median_step_s);
}

std::vector<FrameRecord> ReadFramesCsv(const std::filesystem::path& path) {
  std::ifstream in(path);
  UWS_CHECK(in.good(), path.string(), ": cannot open for reading");
  std::string line;
  UWS_CHECK(static_cast<bool>(std::getline(in, line)), path.string(), ": empty file");
  StripByteOrderMark(line);
  if (!line.empty() && line.back() == '\r') line.pop_back();
  // index,timestamp_s,file then optional laser_angle_rad and laser_on, in
  // that order.
  const std::string base = "index,timestamp_s,file";
  bool with_angle = false, with_on = false;
  if (line.rfind(base, 0) == 0) {
    const std::string rest = line.substr(base.size());
    with_angle = rest == ",laser_angle_rad" || rest == ",laser_angle_rad,laser_on";
    with_on = rest == ",laser_on" || rest == ",laser_angle_rad,laser_on";
    UWS_CHECK(rest.empty() || with_angle || with_on, path.string(),
              ": header must be 'index,timestamp_s,file[,laser_angle_rad][,laser_on]' (got '", line,
              "')");
  } else {
    UWS_THROW(path.string(),
              ": header must be 'index,timestamp_s,file[,laser_angle_rad][,laser_on]' (got '", line,
              "')");
  }
  const size_t num_fields = 3 + (with_angle ? 1 : 0) + (with_on ? 1 : 0);
  std::vector<FrameRecord> records;
  int number = 1;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    std::vector<std::string> fields;
    std::istringstream split(line);
    std::string field;
    while (std::getline(split, field, ',')) fields.push_back(field);
    UWS_CHECK(fields.size() == num_fields, path.string(), ":", number, ": expected ", num_fields,
              " fields");
    FrameRecord record;
    try {
      size_t used = 0;
      record.index = std::stoi(fields[0], &used);
      UWS_CHECK(used == fields[0].size(), "");
      record.timestamp_s = std::stod(fields[1], &used);
      UWS_CHECK(used == fields[1].size(), "");
      if (with_angle) {
        record.laser_angle_rad = std::stod(fields[3], &used);
        UWS_CHECK(used == fields[3].size(), "");
      }
    } catch (const std::exception&) {
      UWS_THROW(path.string(), ":", number,
                ": index, timestamp_s and laser_angle_rad must be numbers");
    }
    if (with_on) {
      const std::string& on = fields.back();
      UWS_CHECK(on == "0" || on == "1", path.string(), ":", number,
                ": laser_on must be 0 or 1 (got '", on, "')");
      record.laser_on = on == "1";
    }
    record.file = fields[2];
    // A frames.csv written on Windows separates folders with '\'.
    std::replace(record.file.begin(), record.file.end(), '\\', '/');
    UWS_CHECK(!record.file.empty(), path.string(), ":", number, ": empty file name");
    UWS_CHECK(std::isfinite(record.timestamp_s) &&
                  (!record.laser_angle_rad || std::isfinite(*record.laser_angle_rad)),
              path.string(), ":", number, ": timestamp_s and laser_angle_rad must be finite");
    // Poses are interpolated and frames placed in time: out of order, a
    // frame would be tracked against the wrong neighbours.
    UWS_CHECK(records.empty() || record.timestamp_s > records.back().timestamp_s, path.string(),
              ":", number, ": timestamps must increase (", fields[1], " after ",
              fmt::format("{:.17g}", records.back().timestamp_s), ")");
    // An index names a frame (of the cloud, of every pose): one frame each.
    UWS_CHECK(records.empty() || record.index > records.back().index, path.string(), ":", number,
              ": frame indices must increase (", record.index, " after ", records.back().index,
              ")");
    records.push_back(record);
  }
  // A camera's or a bag exporter's nanoseconds would pass every check above
  // and make a 14 s scan last years.
  std::vector<double> times;
  for (const FrameRecord& record : records) times.push_back(record.timestamp_s);
  CheckTimestampsInSeconds(times, path.string() + ": timestamp_s");
  // Servo angles in degrees (as the calibration's servo angle file takes
  // them) would turn the sheet by whole turns between frames.
  double lowest = 0.0, highest = 0.0;
  bool angles = false;
  for (const FrameRecord& record : records) {
    if (!record.laser_angle_rad) continue;
    lowest = angles ? std::min(lowest, *record.laser_angle_rad) : *record.laser_angle_rad;
    highest = angles ? std::max(highest, *record.laser_angle_rad) : *record.laser_angle_rad;
    angles = true;
  }
  UWS_CHECK(!angles || (highest - lowest <= M_PI && std::max(-lowest, highest) <= 2.0 * M_PI),
            path.string(), ": laser_angle_rad runs from ", lowest, " to ", highest,
            ", more than a half turn of the servo or beyond a whole one: in degrees? they are "
            "radians (degrees x pi / 180)");
  return records;
}

FramesCsvWriter::FramesCsvWriter(const std::filesystem::path& path, bool with_laser_angle,
                                 bool with_laser_on)
    : file_(path), with_laser_angle_(with_laser_angle), with_laser_on_(with_laser_on) {
  file_.stream() << "index,timestamp_s,file" << (with_laser_angle ? ",laser_angle_rad" : "")
                 << (with_laser_on ? ",laser_on" : "") << "\n";
}

void FramesCsvWriter::Add(const FrameRecord& record) {
  file_.stream() << record.index << "," << fmt::format("{:.17g}", record.timestamp_s) << ","
                 << record.file;
  if (with_laser_angle_)
    file_.stream() << "," << fmt::format("{:.17g}", record.laser_angle_rad.value_or(0.0));
  if (with_laser_on_) file_.stream() << "," << (record.laser_on.value_or(true) ? 1 : 0);
  file_.stream() << "\n";
}

LaserTruthWriter::LaserTruthWriter(const std::filesystem::path& path) : file_(path) {
  file_.stream() << "frame,laser,u,v,x,y,z\n";
}

void LaserTruthWriter::Add(const LaserTruthRow& r) {
  file_.stream() << fmt::format("{},{},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}\n", r.frame, r.laser,
                                r.u, r.v, r.x, r.y, r.z);
}

std::vector<LaserTruthRow> ReadLaserTruthCsv(const std::filesystem::path& path) {
  const CsvTable table = ReadNumericCsv(path, {"frame", "laser", "u", "v", "x", "y", "z"});
  std::vector<LaserTruthRow> rows;
  rows.reserve(table.rows.size());
  for (const auto& row : table.rows) {
    rows.push_back({static_cast<int>(row[0]), static_cast<int>(row[1]), row[2], row[3], row[4],
                    row[5], row[6]});
  }
  return rows;
}

}  // namespace uwscan
