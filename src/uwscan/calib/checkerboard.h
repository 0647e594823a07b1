// Checkerboard corner detection (thesis §4.4 "Robust Checkerboard
// Detection"): OpenCV's findChessboardCornersSB is the thesis's own
// sector-based detector (Duda & Frese 2018); the classic
// findChessboardCorners + cornerSubPix is kept for comparison. Views that
// are blurred, low in contrast, partial or at the image border are rejected
// with a reason.
#pragma once

#include <filesystem>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "uwscan/calib/board.h"

namespace uwscan {

enum class CornerDetector {
  kSectorBased,        // findChessboardCornersSB with CALIB_CB_ACCURACY
  kSectorBasedSubPix,  // SB to find the board, cornerSubPix (11x11) to refine
  kClassic,            // findChessboardCorners + cornerSubPix (11x11)
};
const char* CornerDetectorName(CornerDetector detector);
// "sb" | "sb-subpix" | "classic"; nullopt otherwise.
std::optional<CornerDetector> CornerDetectorFromName(const std::string& name);

struct DetectionOptions {
  CornerDetector detector = CornerDetector::kSectorBased;
  double max_edge_width_px = 6.0;  // cv::estimateChessboardSharpness above this: blurred
  double min_contrast = 15.0;      // grey levels between black and white squares
  double border_margin_px = 3.0;   // corners closer to the border: partial view
  // Colour images: leave this channel (0 red, 1 green, 2 blue) out of the
  // grey image, e.g. the laser's in laser calibration, so that the line
  // neither hides the dim board from the contrast stretch nor looks like an
  // edge to the sharpness measure. -1: all channels.
  int ignore_channel = -1;
  bool progress = true;  // DetectBoardsInFolder: a progress bar on a terminal
  void Check() const;
};

struct BoardDetection {
  std::string name;
  bool found = false;
  std::string reason;           // why not, empty when found
  int corners = 0;              // detected corners (0 or the board's count)
  double edge_width_px = -1.0;  // sharpness: 10-90 % edge rise width, -1 if unknown
  double contrast = -1.0;
  std::vector<Eigen::Vector2d> points;  // board order
};

// Detects one board in an 8-bit grey or BGR image.
BoardDetection DetectBoard(const cv::Mat& image, const BoardSpec& board,
                           const DetectionOptions& options);

struct FolderDetection {
  std::vector<BoardDetection> images;  // every image, sorted by file name
  CornerSet set;                       // the found boards
};

// Every .png/.jpg/.jpeg/.bmp/.tif(f) in `folder`, the images on all cores
// (results as on one). Throws uwscan::Error if the folder has no images,
// they differ in size, or no board is found in any.
FolderDetection DetectBoardsInFolder(const std::filesystem::path& folder, const BoardSpec& board,
                                     const DetectionOptions& options);

}  // namespace uwscan
