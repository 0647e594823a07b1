// A dataset folder as the visual odometry reads it (architecture.md:
// rig.yaml, frames.csv, frames/*.png, groundtruth.tum); frames.csv is read
// by io/dataset.h, as everywhere.
#pragma once

#include <filesystem>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "uwscan/io/dataset.h"
#include "uwscan/io/tum_trajectory.h"
#include "uwscan/sensor/rig.h"

namespace uwscan {

struct VoDataset {
  std::filesystem::path dir;
  Rig rig;
  std::vector<FrameRecord> frames;
  std::optional<TumTrajectory> ground_truth;
};

// Reads rig.yaml, frames.csv and (if present) groundtruth.tum; errors name
// the file and line. Images are read later, frame by frame.
VoDataset ReadVoDataset(const std::filesystem::path& dir);

// Reads a frame as stored (8/16-bit, mono, colour or raw Bayer); empty Mat
// if the file is missing or unreadable (the caller warns and marks a gap).
cv::Mat ReadFrameImage(const VoDataset& dataset, const FrameRecord& frame);
// Grey image for tracking: demosaics raw Bayer (rig `bayer`) and takes the
// green channel of colour images; 16-bit stays 16-bit.
cv::Mat TrackingImage(const cv::Mat& raw, const std::string& bayer);

}  // namespace uwscan
