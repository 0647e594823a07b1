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

  // Index of a named column; throws uwscan::Error naming `source` if absent.
  int Column(const std::string& name, const std::string& source) const;
};

// Reads a numeric CSV. Every error names the file and the line.
CsvTable ReadNumericCsv(const std::filesystem::path& path);

// Writes atomically with 17 significant digits (round trips doubles exactly).
void WriteNumericCsv(const std::filesystem::path& path, const CsvTable& table);

}  // namespace uwscan
