#include "uwscan/laser/scanline.h"

#include <array>
#include <cmath>

#include "uwscan/util/error.h"

namespace uwscan::laser {
namespace {

// Colour at (row % 2, col % 2) for each Bayer pattern.
using Pattern = std::array<std::array<int, 2>, 2>;

Pattern BayerPattern(ColourLayout layout) {
  switch (layout) {
    case ColourLayout::kBayerRggb:
      return {{{kRed, kGreen}, {kGreen, kBlue}}};
    case ColourLayout::kBayerBggr:
      return {{{kBlue, kGreen}, {kGreen, kRed}}};
    case ColourLayout::kBayerGrbg:
      return {{{kGreen, kRed}, {kBlue, kGreen}}};
    case ColourLayout::kBayerGbrg:
      return {{{kGreen, kBlue}, {kRed, kGreen}}};
    default:
      UWS_THROW("not a Bayer layout");
  }
}

constexpr double kLogGain = 64.0;

}  // namespace

const std::vector<uint16_t>& LogTable(int depth) {
  const auto make = [](int levels) {
    std::vector<uint16_t> t(levels);
    for (int i = 0; i < levels; ++i) {
      t[i] = static_cast<uint16_t>(std::lround(
          kLogScale * std::log1p(kLogGain * i / (levels - 1.0)) / std::log1p(kLogGain)));
    }
    return t;
  };
  static const std::vector<uint16_t> table8 = make(256);
  static const std::vector<uint16_t> table16 = make(65536);
  return depth == CV_8U ? table8 : table16;
}

ColourLayout TransposedLayout(ColourLayout layout) {
  switch (layout) {
    case ColourLayout::kBayerGrbg:
      return ColourLayout::kBayerGbrg;
    case ColourLayout::kBayerGbrg:
      return ColourLayout::kBayerGrbg;
    default:
      return layout;  // mono, BGR, RGGB and BGGR are symmetric
  }
}

int BayerColourAt(ColourLayout layout, int row, int col) {
  if (layout == ColourLayout::kMono || layout == ColourLayout::kBgr) return kMono;
  return BayerPattern(layout)[row % 2][col % 2];
}

void FullResolutionGreen(const cv::Mat& image, ColourLayout layout, int row, int first, int count,
                         std::vector<float>* out) {
  out->resize(count);
  const float scale = image.depth() == CV_8U ? 1.0f / 255.0f : 1.0f / 65535.0f;
  const auto at = [&](int r, int c) -> float {
    return image.depth() == CV_8U ? image.at<uint8_t>(r, c) : image.at<uint16_t>(r, c);
  };
  for (int i = 0; i < count; ++i) {
    const int col = first + i;
    if (BayerColourAt(layout, row, col) == kGreen) {
      (*out)[i] = at(row, col) * scale;
      continue;
    }
    float sum = 0.0f;
    int n = 0;
    for (const int r : {row - 1, row + 1}) {
      if (r >= 0 && r < image.rows) sum += at(r, col), ++n;
    }
    (*out)[i] = n ? sum / n * scale : 0.0f;
  }
}

void FullResolutionChannel(const cv::Mat& image, ColourLayout layout, int row, int channel,
                           int first, int count, std::vector<float>* out) {
  out->resize(count);
  const float scale = image.depth() == CV_8U ? 1.0f / 255.0f : 1.0f / 65535.0f;
  const auto at = [&](int r, int c) -> float {
    return image.depth() == CV_8U ? image.at<uint8_t>(r, c) : image.at<uint16_t>(r, c);
  };
  if (layout == ColourLayout::kBgr) {
    for (int i = 0; i < count; ++i) {
      const int col = first + i;
      (*out)[i] = (image.depth() == CV_8U ? image.at<cv::Vec3b>(row, col)[2 - channel]
                                          : image.at<cv::Vec3w>(row, col)[2 - channel]) *
                  scale;
    }
    return;
  }
  UWS_CHECK(layout != ColourLayout::kMono && (channel == kRed || channel == kBlue),
            "FullResolutionChannel: red or blue of a Bayer mosaic");
  int colour_row = 0, colour_col = 0;  // parity of the pixels of this colour
  for (int r = 0; r < 2; ++r) {
    for (int c = 0; c < 2; ++c) {
      if (BayerColourAt(layout, r, c) == channel) colour_row = r, colour_col = c;
    }
  }
  int rows[2], row_count = 0;
  if (row % 2 == colour_row) {
    rows[row_count++] = row;
  } else {
    if (row > 0) rows[row_count++] = row - 1;
    if (row + 1 < image.rows) rows[row_count++] = row + 1;
  }
  for (int i = 0; i < count; ++i) {
    const int col = first + i;
    float sum = 0.0f;
    int n = 0;
    for (int k = 0; k < row_count; ++k) {
      if (col % 2 == colour_col) {
        sum += at(rows[k], col), ++n;
        continue;
      }
      if (col > 0) sum += at(rows[k], col - 1), ++n;
      if (col + 1 < image.cols) sum += at(rows[k], col + 1), ++n;
    }
    (*out)[i] = n ? sum / n * scale : 0.0f;
  }
}

std::vector<ScanChannel> ChannelsOnRow(ColourLayout layout, int row) {
  if (layout == ColourLayout::kMono) return {{kMono, 0, 1}};
  if (layout == ColourLayout::kBgr) return {{kRed, 0, 1}, {kGreen, 0, 1}, {kBlue, 0, 1}};
  const Pattern pattern = BayerPattern(layout);
  return {{pattern[row % 2][0], 0, 2}, {pattern[row % 2][1], 1, 2}};
}

RowSamples RowChannel(const cv::Mat& image, ColourLayout layout, int row,
                      const ScanChannel& channel) {
  RowSamples samples;
  if (layout == ColourLayout::kBgr) {
    samples.first = 2 - channel.channel;  // BGR storage
    samples.step = 3;
    samples.count = image.cols;
  } else {
    samples.first = channel.offset;
    samples.step = channel.stride;
    samples.count = (image.cols - channel.offset + channel.stride - 1) / channel.stride;
  }
  if (image.depth() == CV_8U) {
    samples.data8 = image.ptr<uint8_t>(row);
    samples.scale = 1.0f / 255.0f;
  } else {
    samples.data16 = image.ptr<uint16_t>(row);
    samples.scale = 1.0f / 65535.0f;
  }
  return samples;
}

}  // namespace uwscan::laser
