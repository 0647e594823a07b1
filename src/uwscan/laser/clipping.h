// How much of the scene is at full scale in the laser's colour, away from
// the line. Where the scene itself clips, a line on it cannot stand out: the
// detector loses it there or takes texture beside it for the line (a mono
// camera at a colour camera's exposure, a white target under the floods).
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "uwscan/laser/detector.h"

namespace uwscan::laser {

// A frame with this share of its scene clipped has lost the line on part
// of it; the reports warn when this many of the frames (or more) have.
constexpr double kClippedFrameShare = 0.01;
constexpr double kClippedFramesToWarn = 0.1;

// What the reports say when kClippedFramesToWarn of the frames or more are
// clipped: `frames_clipped` of them, and the share of all samples clipped.
std::string ClippedSceneWarning(int frames_clipped, double share);

// The features' colour (the floods', which the self-referenced odometry
// tracks beside the laser's): a frame with this share of it at full scale
// has lost the texture there. A light's hot spot on something close clips a
// little in many scans; this much is an exposure set too high.
constexpr double kClippedFeaturesFrameShare = 0.05;
// What reconstruct says when kClippedFramesToWarn of the frames or more
// have: `frames_clipped` of them, the share of all samples clipped, and
// the colour's name.
std::string ClippedFeaturesWarning(int frames_clipped, double share, const std::string& colour);

struct ClippedScene {
  long clipped = 0;   // samples at full scale
  long examined = 0;  // samples looked at
  double Share() const { return examined > 0 ? static_cast<double>(clipped) / examined : 0.0; }
};

// The laser channel's samples on every `every_rows`-th image row (a raw
// Bayer mosaic: the pixels of the laser's colour; mono and BGR images: the
// laser's channel), without those within `margin_px` along the scan line of
// the line's point on that scan line (`line`, as DetectLaserLine found it:
// the line itself is often at full scale). Full scale: 255 for 8-bit
// images, 65470 (99.9 %) and up for 16-bit ones.
ClippedScene MeasureClipping(const cv::Mat& image, ColourLayout layout, int laser_channel,
                             bool scan_rows, const std::vector<LaserPoint>& line,
                             int every_rows = 8, double margin_px = 12.0);

}  // namespace uwscan::laser
