#include "uwscan/util/csv.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "uwscan/util/atomic_file.h"
#include "uwscan/util/error.h"

namespace uwscan {
namespace {

std::vector<std::string> SplitLine(const std::string& line) {
  std::vector<std::string> fields;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, ',')) {
    const auto first = field.find_first_not_of(" \t\r");
    const auto last = field.find_last_not_of(" \t\r");
    fields.push_back(first == std::string::npos ? "" : field.substr(first, last - first + 1));
  }
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

}  // namespace

void StripByteOrderMark(std::string& first_line) {
  if (first_line.rfind("\xEF\xBB\xBF", 0) == 0) first_line.erase(0, 3);
}

CsvTable ReadNumericCsv(const std::filesystem::path& path,
                        const std::vector<std::string>& columns) {
  std::ifstream in(path);
  UWS_CHECK(in.good(), path.string(), ": cannot open for reading");
  std::string line;
  UWS_CHECK(static_cast<bool>(std::getline(in, line)), path.string(),
            ": empty file (expected a header line)");
  StripByteOrderMark(line);
  const std::vector<std::string> header = SplitLine(line);
  std::vector<int> indices;
  for (const std::string& name : columns) {
    const auto found = std::find(header.begin(), header.end(), name);
    UWS_CHECK(found != header.end(), path.string(), ": missing column '", name, "' (header '",
              line.substr(0, line.find_last_not_of("\r") + 1),
              "'; columns are separated by commas)");
    indices.push_back(static_cast<int>(found - header.begin()));
  }
  CsvTable table;
  table.header = columns;
  int line_number = 1;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const auto fields = SplitLine(line);
    UWS_CHECK(fields.size() == header.size(), path.string(), ":", line_number, ": expected ",
              header.size(), " fields, found ", fields.size());
    std::vector<double> row(columns.size());
    for (size_t i = 0; i < columns.size(); ++i) {
      const std::string& f = fields[indices[i]];
      const auto result = std::from_chars(f.data(), f.data() + f.size(), row[i]);
      UWS_CHECK(
          result.ec == std::errc() && result.ptr == f.data() + f.size() && std::isfinite(row[i]),
          path.string(), ":", line_number, ": column '", columns[i], "' is not a finite number: '",
          f, "'");
    }
    table.rows.push_back(std::move(row));
  }
  return table;
}

void WriteNumericCsv(const std::filesystem::path& path, const CsvTable& table) {
  AtomicFile file(path);
  auto& out = file.stream();
  for (size_t i = 0; i < table.header.size(); ++i) out << (i ? "," : "") << table.header[i];
  out << '\n';
  char buffer[64];
  for (const auto& row : table.rows) {
    for (size_t i = 0; i < row.size(); ++i) {
      const auto result = std::to_chars(buffer, buffer + sizeof(buffer), row[i]);
      if (i) out << ',';
      out.write(buffer, result.ptr - buffer);
    }
    out << '\n';
  }
  file.Commit();
}

}  // namespace uwscan
