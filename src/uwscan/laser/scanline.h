// Access to one scan line of an image, one colour channel at a time: for a
// raw Bayer mosaic a channel is sampled every other pixel along the line.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "uwscan/laser/detector.h"

namespace uwscan::laser {

// Samples i of a channel on a scan line sit at full-resolution position
// offset + stride * i along the line.
struct ScanChannel {
  int channel = kMono;
  int offset = 0;
  int stride = 1;
};

// The samples of one channel on one row, read in place.
struct RowSamples {
  const uint8_t* data8 = nullptr;  // one of the two is set
  const uint16_t* data16 = nullptr;
  int first = 0;  // element index of sample 0
  int step = 1;   // elements between samples
  int count = 0;
  float scale = 1.0f;  // to [0, 1]

  int Value(int i) const { return data8 ? data8[first + i * step] : data16[first + i * step]; }
  float Raw(int i) const { return Value(i) * scale; }
};

// The layout of the transposed image (scanning columns = rows of the transpose).
ColourLayout TransposedLayout(ColourLayout layout);

// Colour of a raw Bayer pixel (kMono for mono and BGR layouts).
int BayerColourAt(ColourLayout layout, int row, int col);

// Green samples of a raw Bayer row at full resolution over columns
// [first, first + count): green pixels as they are, the others the mean of
// the green pixels above and below (no shift along the row, so a line's
// position is not biased). Normalised to [0, 1].
void FullResolutionGreen(const cv::Mat& image, ColourLayout layout, int row, int first, int count,
                         std::vector<float>* out);

// Samples of colour `channel` (kRed or kBlue of a raw Bayer mosaic, or any
// channel of a BGR image) at full resolution over columns [first, first +
// count) of `row`: for a mosaic the mean of that colour's nearest pixels on
// this row or the rows above and below, in this column or the two beside it.
// Normalised to [0, 1].
void FullResolutionChannel(const cv::Mat& image, ColourLayout layout, int row, int channel,
                           int first, int count, std::vector<float>* out);

// Channels present on row `row` (at most three).
std::vector<ScanChannel> ChannelsOnRow(ColourLayout layout, int row);

RowSamples RowChannel(const cv::Mat& image, ColourLayout layout, int row,
                      const ScanChannel& channel);

// The thesis's logarithmic scaling (§5.3) as a table from raw value to
// kLogScale * log(1 + k x) / log(1 + k), x in [0, 1], k = 64: it compresses
// highlights (a bright line's width no longer depends on its power) while
// staying nearly linear in the dark, where a pure log would amplify noise.
constexpr int kLogScale = 4096;
const std::vector<uint16_t>& LogTable(int depth);

}  // namespace uwscan::laser
