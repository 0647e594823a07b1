#include "uwscan/laser/colour_signature.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <utility>

#include "uwscan/laser/scanline.h"
#include "uwscan/util/statistics.h"

namespace uwscan::laser {
namespace {

// DetectorOptions::min_signature_share: how much light a peak adds above
// its flanks (their mean, fraction of full scale), summed across the line,
// in the laser's colour and in the third colour, both read where the third
// colour has its own pixels: a mosaic samples each colour every other
// column, and the share a line narrower than that shows would depend on
// where it falls between them. For a mosaic, on the row next to the
// peak's with the third colour; the laser's colour there interpolated at
// full resolution. Summed, a slanted line blurred by that interpolation
// still gives its whole light.
struct ColourHeights {
  double laser = 0.0, signature = 0.0;
};

ColourHeights HeightsAt(const cv::Mat& image, ColourLayout layout, int laser_channel,
                        int signature_channel, const Peak& peak, double line_sigma_px,
                        std::vector<float>* laser, std::vector<float>* signature) {
  const bool mosaic = layout != ColourLayout::kBgr;
  int row = peak.line;
  if (mosaic && BayerColourAt(layout, row, 0) != signature_channel &&
      BayerColourAt(layout, row, 1) != signature_channel) {
    row = row + 1 < image.rows ? row + 1 : row - 1;
    if (row < 0) return {};  // a one-row mosaic
  }
  const int core = std::max(1, static_cast<int>(std::lround(line_sigma_px))) + 2;
  const int outer = std::max(core + 4, static_cast<int>(std::lround(4.0 * line_sigma_px)));
  const int centre = static_cast<int>(std::lround(peak.position));
  const int lo = std::max(0, centre - outer), hi = std::min(image.cols - 1, centre + outer);
  if (mosaic && laser_channel == kGreen) {
    FullResolutionGreen(image, layout, row, lo, hi - lo + 1, laser);
  } else {
    FullResolutionChannel(image, layout, row, laser_channel, lo, hi - lo + 1, laser);
  }
  FullResolutionChannel(image, layout, row, signature_channel, lo, hi - lo + 1, signature);
  double laser_core = 0.0, signature_core = 0.0, laser_flank = 0.0, signature_flank = 0.0;
  int core_count = 0, flank_count = 0;
  for (int c = lo; c <= hi; ++c) {
    if (mosaic && BayerColourAt(layout, row, c) != signature_channel) continue;
    const int i = c - lo;
    if (std::abs(c - centre) <= core) {
      laser_core += (*laser)[i], signature_core += (*signature)[i], ++core_count;
    } else if (std::abs(c - centre) > core + 1) {
      laser_flank += (*laser)[i], signature_flank += (*signature)[i], ++flank_count;
    }
  }
  if (core_count == 0 || flank_count == 0) return {};
  return {std::max(0.0, laser_core - core_count * laser_flank / flank_count),
          std::max(0.0, signature_core - core_count * signature_flank / flank_count)};
}

}  // namespace

void DropOffColourSegments(const cv::Mat& image, ColourLayout layout, const DetectorOptions& o,
                           const std::vector<Peak>& peaks, std::vector<Segment>* segments,
                           DetectionStats* stats) {
  stats->colour_signature = 0.0;
  stats->off_colour_segments = stats->off_colour_peaks = 0;
  const int signature_channel = SignatureChannelFor(o.laser_channel);
  if (!(o.min_signature_share > 0.0) || layout == ColourLayout::kMono || signature_channel < 0) {
    return;
  }
  // Summed across the line, of full scale: bright enough for its share in
  // the third colour (a tenth or so) to stand well above a grey level.
  constexpr double kBrightPeak = 0.3;
  constexpr size_t kMinBrightPeaks = 20;
  std::vector<float> laser_scratch, signature_scratch;
  std::vector<double> ratios;
  std::vector<std::pair<double, double>> sums(segments->size());  // laser, signature
  for (size_t s = 0; s < segments->size(); ++s) {
    const Segment& segment = (*segments)[s];
    if (static_cast<int>(segment.peaks.size()) < o.min_segment_lines) continue;
    for (int index : segment.peaks) {
      const ColourHeights h =
          HeightsAt(image, layout, o.laser_channel, signature_channel, peaks[index],
                    o.line_sigma_px, &laser_scratch, &signature_scratch);
      sums[s].first += h.laser;
      sums[s].second += h.signature;
      if (h.laser >= kBrightPeak) ratios.push_back(h.signature / h.laser);
    }
  }
  if (ratios.size() < kMinBrightPeaks) return;
  const double share = Median(ratios);
  stats->colour_signature = share;
  std::vector<Segment> kept;
  kept.reserve(segments->size());
  for (size_t s = 0; s < segments->size(); ++s) {
    Segment& segment = (*segments)[s];
    const double n = static_cast<double>(segment.peaks.size());
    const double expected = share * sums[s].first;
    if (static_cast<int>(n) >= o.min_segment_lines && expected >= o.min_signature_height * n &&
        sums[s].second < o.min_signature_share * expected) {
      ++stats->off_colour_segments;
      stats->off_colour_peaks += static_cast<int>(n);
      continue;
    }
    kept.push_back(std::move(segment));
  }
  segments->swap(kept);
}

}  // namespace uwscan::laser
