// Minimal reader of a dataset folder for the visual odometry
// (architecture.md: rig.yaml, frames.csv, frames/*.png, groundtruth.tum).
// The simulator issue brings io/dataset.*; the lead will unify the two.
#pragma once

#include <filesystem>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "uwscan/io/tum_trajectory.h"
#include "uwscan/sensor/rig.h"

namespace uwscan {

struct VoFrameEntry {
  int index = 0;
  double timestamp_s = 0.0;
  std::string file;  // relative to the dataset folder
  std::optional<double> laser_angle_rad;
};

struct VoDataset {
  std::filesystem::path dir;
  Rig rig;
  std::vector<VoFrameEntry> frames;
  std::optional<TumTrajectory> ground_truth;
};

// Reads rig.yaml, frames.csv and (if present) groundtruth.tum; errors name
// the file and line. Images are read later, frame by frame.
VoDataset ReadVoDataset(const std::filesystem::path& dir);
std::vector<VoFrameEntry> ParseFramesCsv(const std::string& text, const std::string& source);

// Reads a frame as stored (8/16-bit, mono, colour or raw Bayer); empty Mat
// if the file is missing or unreadable (the caller warns and marks a gap).
cv::Mat ReadFrameImage(const VoDataset& dataset, const VoFrameEntry& frame);
// Grey image for tracking: demosaics raw Bayer (rig `bayer`) and takes the
// green channel of colour images; 16-bit stays 16-bit.
cv::Mat TrackingImage(const cv::Mat& raw, const std::string& bayer);

// Writes frames.csv (with header) atomically.
void WriteFramesCsv(const std::filesystem::path& path, const std::vector<VoFrameEntry>& frames);

}  // namespace uwscan
