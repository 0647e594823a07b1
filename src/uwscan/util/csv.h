// Minimal CSV with a header line: numeric tables as used by the CLI
// (points.csv, pixels.csv, rays.csv, laser_gt.csv).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace uwscan {

struct CsvTable {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
};

// Reads the named columns of a CSV with a header line, in that order (the
// table's header is `columns`); other columns, numeric or not, are skipped.
// Every error names the file, and the line or the missing column.
CsvTable ReadNumericCsv(const std::filesystem::path& path, const std::vector<std::string>& columns);

// Removes a UTF-8 byte order mark from the start of a file's first line
// (Windows editors and Excel save text with one).
void StripByteOrderMark(std::string& first_line);

// Writes atomically with 17 significant digits (round trips doubles exactly).
void WriteNumericCsv(const std::filesystem::path& path, const CsvTable& table);

}  // namespace uwscan
