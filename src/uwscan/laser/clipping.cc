#include "uwscan/laser/clipping.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "uwscan/laser/scanline.h"
#include "uwscan/util/error.h"

namespace uwscan::laser {

namespace {

// Elements p[i * step], i in [from, to), at or above `full_scale`; a step
// known at compile time lets the compiler vectorise the strided loads.
template <int kStep, typename T>
long CountAtLeast(const T* p, int from, int to, int full_scale) {
  long clipped = 0;
  for (int i = from; i < to; ++i) clipped += p[i * kStep] >= full_scale;
  return clipped;
}

// Samples [from, to) of `samples` at or above `full_scale`.
template <typename T>
long CountClipped(const T* p, int step, int from, int to, int full_scale) {
  switch (step) {
    case 1:
      return CountAtLeast<1>(p, from, to, full_scale);
    case 2:
      return CountAtLeast<2>(p, from, to, full_scale);
    case 3:
      return CountAtLeast<3>(p, from, to, full_scale);
    default: {
      long clipped = 0;
      for (int i = from; i < to; ++i) clipped += p[i * step] >= full_scale;
      return clipped;
    }
  }
}

long CountClipped(const RowSamples& samples, int from, int to, int full_scale) {
  return samples.data8
             ? CountClipped(samples.data8 + samples.first, samples.step, from, to, full_scale)
             : CountClipped(samples.data16 + samples.first, samples.step, from, to, full_scale);
}

}  // namespace

std::string ClippedSceneWarning(int frames_clipped, double share) {
  return fmt::format(
      "in {} frame(s) the scene itself is at full scale in the laser's colour on {:.0f} % or "
      "more of the image away from the line ({:.1f} % over all frames): where it is, the line "
      "cannot stand out, and it is lost there or texture beside it is taken for it; lower the "
      "camera's exposure or gain (a mono camera gathers about three times the light of a colour "
      "one)",
      frames_clipped, 100.0 * kClippedFrameShare, 100.0 * share);
}

std::string ClippedFeaturesWarning(int frames_clipped, double share, const std::string& colour) {
  return fmt::format(
      "in {} frame(s) the features' colour ({}, lit by the floods) is at full scale on {:.0f} % "
      "or more of the image ({:.1f} % over all frames): the odometry finds no texture to track "
      "where it is, and the poses suffer; lower the camera's exposure or gain, or the floods' "
      "power",
      frames_clipped, colour, 100.0 * kClippedFeaturesFrameShare, 100.0 * share);
}

ClippedScene MeasureClipping(const cv::Mat& image, ColourLayout layout, int laser_channel,
                             bool scan_rows, const std::vector<LaserPoint>& line, int every_rows,
                             double margin_px) {
  UWS_CHECK(image.depth() == CV_8U || image.depth() == CV_16U,
            "clipping: images must be 8- or 16-bit");
  UWS_CHECK(every_rows >= 1, "clipping: every_rows must be >= 1, got ", every_rows);
  // The line's position on each scan line (image rows when scanning rows,
  // columns otherwise); NaN where it has none.
  const int scan_lines = scan_rows ? image.rows : image.cols;
  std::vector<double> line_at(scan_lines, std::numeric_limits<double>::quiet_NaN());
  for (const LaserPoint& p : line) {
    const long index = std::lround(scan_rows ? p.v : p.u);
    if (index >= 0 && index < scan_lines) line_at[index] = scan_rows ? p.u : p.v;
  }
  const int full_scale = image.depth() == CV_8U ? 255 : 65470;
  const int channel = layout == ColourLayout::kMono ? kMono : laser_channel;
  ClippedScene result;
  for (int row = 0; row < image.rows; row += every_rows) {
    for (const ScanChannel& c : ChannelsOnRow(layout, row)) {
      if (c.channel != channel) continue;
      const RowSamples samples = RowChannel(image, layout, row, c);
      if (scan_rows) {
        // The samples within margin_px of the line's column: [from, to).
        int from = samples.count, to = samples.count;
        if (const double u = line_at[row]; std::isfinite(u)) {
          from = std::clamp(static_cast<int>(std::ceil((u - margin_px - c.offset) / c.stride)), 0,
                            samples.count);
          to = std::clamp(static_cast<int>(std::floor((u + margin_px - c.offset) / c.stride)) + 1,
                          from, samples.count);
        }
        result.examined += samples.count - (to - from);
        result.clipped += CountClipped(samples, 0, from, full_scale) +
                          CountClipped(samples, to, samples.count, full_scale);
        continue;
      }
      for (int i = 0; i < samples.count; ++i) {
        const double on_line = line_at[c.offset + c.stride * i];
        if (std::abs(row - on_line) <= margin_px) continue;  // NaN: false
        ++result.examined;
        result.clipped += samples.Value(i) >= full_scale;
      }
    }
  }
  return result;
}

}  // namespace uwscan::laser
