#include "uwscan/laser/detector.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "uwscan/laser/colour_signature.h"
#include "uwscan/laser/scanline.h"
#include "uwscan/laser/segments.h"
#include "uwscan/laser/subpixel.h"
#include "uwscan/util/error.h"
#include "uwscan/util/statistics.h"

namespace uwscan::laser {

namespace {

// Band-pass across the line (§5.3): a difference of box means, inner
// half-width a ~ sigma, outer half-width b ~ 4 sigma; zero response to a
// constant signal. Integer arithmetic on the log-scaled samples from a
// prefix sum: O(1) per sample and exact.
struct BandPass {
  int inner = 1;
  int outer = 4;
  std::vector<int32_t> prefix;

  // Response units: kLogScale * (2a + 1) * (2b + 1) per unit of log contrast.
  double Scale() const { return double(kLogScale) * (2 * inner + 1) * (2 * outer + 1); }

  void Apply(const RowSamples& row, const std::vector<uint16_t>& table,
             std::vector<int32_t>* band) {
    const int n = row.count;
    // Log scaling through the table fused with the prefix sum.
    prefix.resize(n + 1);
    int32_t* __restrict p = prefix.data();
    p[0] = 0;
    int32_t sum = 0;
    if (row.data8) {
      const uint8_t* __restrict data = row.data8 + row.first;
      const int step = row.step;
      for (int i = 0; i < n; ++i) p[i + 1] = sum += table[data[i * step]];
    } else {
      const uint16_t* __restrict data = row.data16 + row.first;
      const int step = row.step;
      for (int i = 0; i < n; ++i) p[i + 1] = sum += table[data[i * step]];
    }
    band->resize(n);
    int32_t* __restrict out = band->data();
    // Locals (not members) so that the compiler can count and vectorise.
    const int a = inner, b = outer;
    const int32_t wi = 2 * a + 1, wo = 2 * b + 1;
    const int begin = std::min(b, n), end = std::max(begin, n - b);
    for (int i = 0; i < begin; ++i) out[i] = 0;
    // Four shifted views of the prefix sum.
    const int32_t* __restrict inner_hi = p + a + 1;
    const int32_t* __restrict inner_lo = p - a;
    const int32_t* __restrict outer_hi = p + b + 1;
    const int32_t* __restrict outer_lo = p - b;
    for (int i = begin; i < end; ++i) {
      out[i] = (inner_hi[i] - inner_lo[i]) * wo - (outer_hi[i] - outer_lo[i]) * wi;
    }
    for (int i = end; i < n; ++i) out[i] = 0;
  }
};

constexpr float kSaturation = 0.999f;

// The samples across the line that the sub-pixel fit reads, and the
// albedo channel's at the same positions (DetectorOptions::albedo_channel).
struct PeakProfile {
  std::vector<float> laser;
  std::vector<float> reference;  // empty: no albedo test here
  int lo = 0;                    // full-resolution position of sample 0 is origin + step * lo
  int origin = 0, step = 1;
  int best = 0;        // index of the raw maximum
  int half_width = 1;  // of the Gaussian fit, samples
};

struct Scratch {
  std::vector<int32_t> band;
  std::vector<int> candidates;
  std::vector<uint8_t> maximum_flags;  // per sample: a local maximum above the threshold
  std::vector<PeakProfile> profiles;   // of the selected peaks
  BandPass bandpass;
};

const ScanChannel* FindLaserChannel(const std::vector<ScanChannel>& channels, int laser_channel) {
  for (const auto& c : channels) {
    if (c.channel == laser_channel || c.channel == kMono) return &c;
  }
  return nullptr;
}

// Band-pass response at one sample, from the log-scaled samples around it
// (same units as BandPass::Apply); 0 where the support leaves the line.
int32_t LocalBand(const RowSamples& row, const std::vector<uint16_t>& table, int k, int inner,
                  int outer) {
  if (k - outer < 0 || k + outer >= row.count) return 0;
  int32_t inner_sum = 0, outer_sum = 0;
  for (int j = k - outer; j <= k + outer; ++j) {
    const int32_t v = table[row.Value(j)];
    outer_sum += v;
    if (j >= k - inner && j <= k + inner) inner_sum += v;
  }
  return inner_sum * (2 * outer + 1) - outer_sum * (2 * inner + 1);
}

// §5.5: true if another colour responds at least as strongly as the laser's
// colour at this position: on this row and, for a Bayer mosaic, on the rows
// above and below (each colour is missing from every other row).
bool StrongerInOtherChannel(const cv::Mat& image, ColourLayout layout, int row,
                            const ScanChannel& laser, double position, int32_t response,
                            const BandPass& bandpass) {
  const auto& table = LogTable(image.depth());
  const bool bayer = laser.stride == 2;
  for (int r = bayer ? row - 1 : row; r <= (bayer ? row + 1 : row); ++r) {
    if (r < 0 || r >= image.rows) continue;
    for (const auto& c : ChannelsOnRow(layout, r)) {
      if (c.channel == laser.channel) continue;
      const RowSamples samples = RowChannel(image, layout, r, c);
      const int k = static_cast<int>(std::lround((position - c.offset) / c.stride));
      for (int j = k - 1; j <= k + 1; ++j) {
        if (LocalBand(samples, table, j, bandpass.inner, bandpass.outer) >= response) return true;
      }
    }
  }
  return false;
}

// A peak (scan-line coordinates) as an image point.
LaserPoint ToLaserPoint(const Peak& p, bool scan_rows) {
  LaserPoint point;
  point.u = scan_rows ? p.position : p.line;
  point.v = scan_rows ? p.line : p.position;
  point.channel = p.channel;
  point.strength = p.strength;
  return point;
}

// Drops the peaks `exclude` flags (position along the scan line, line);
// returns how many.
int ExcludePeaks(const std::function<bool(double, int)>& exclude, std::vector<Peak>* peaks) {
  const size_t before = peaks->size();
  peaks->erase(std::remove_if(peaks->begin(), peaks->end(),
                              [&](const Peak& p) { return exclude(p.position, p.line); }),
               peaks->end());
  return static_cast<int>(before - peaks->size());
}

// Thesis method, steps 1-4 and 7 on one scan line: peaks of the laser
// channel; only those within o.line_window_px of the line's prior on this
// scan line, if it has one.
void FindLinePeaks(const cv::Mat& image, ColourLayout layout, int row, const DetectorOptions& o,
                   Scratch* s, std::vector<Peak>* peaks, DetectionStats* stats) {
  const auto channels = ChannelsOnRow(layout, row);
  const ScanChannel* laser = FindLaserChannel(channels, o.laser_channel);
  if (!laser) return;  // e.g. a Bayer row without the laser's colour
  RowSamples samples = RowChannel(image, layout, row, *laser);
  int skipped = 0;  // samples before the window
  if (row < static_cast<int>(o.line_prior.size()) && std::isfinite(o.line_prior[row].first)) {
    const auto [from, to] = o.line_prior[row];
    skipped = std::clamp(
        static_cast<int>(std::floor((from - o.line_window_px - laser->offset) / laser->stride)), 0,
        samples.count);
    const int end = std::clamp(
        static_cast<int>(std::ceil((to + o.line_window_px - laser->offset) / laser->stride)) + 1,
        skipped, samples.count);
    samples.first += skipped * samples.step;
    samples.count = end - skipped;
    if (samples.count < 3) return;  // the window lies off the scan line
  }
  const double sigma = o.line_sigma_px / laser->stride;
  BandPass& bandpass = s->bandpass;
  bandpass.inner = std::max(1, static_cast<int>(std::lround(sigma)));
  bandpass.outer = std::max(bandpass.inner + 2, static_cast<int>(std::lround(4.0 * sigma)));
  bandpass.Apply(samples, LogTable(image.depth()), &s->band);  // steps 1 and 2
  const double scale = bandpass.Scale();
  const int32_t threshold = static_cast<int32_t>(std::ceil(o.min_strength * scale));
  const int n = samples.count;
  const int a = bandpass.inner, outer = bandpass.outer;
  const int noise_half = std::max(outer + 2, o.noise_half_window_px / laser->stride);
  const int32_t* band = s->band.data();
  // Step 4, non-maximum suppression: local maxima above the threshold.
  // On a textured tank frame some 40 of a row's 640 samples, scattered, so
  // a branch per sample mispredicts: one flag byte per sample (no store
  // whose address depends on the data), then eight flags at a time, most
  // of them all zero, and the set ones in order by their lowest bit.
  // (The scratch keeps its size across rows: no re-initialisation per row.)
  auto& candidates = s->candidates;
  if (static_cast<int>(candidates.size()) < n) candidates.resize(n);
  const int padded = (n + 7) / 8 * 8;
  auto& flags = s->maximum_flags;
  if (static_cast<int>(flags.size()) < padded) flags.resize(padded);
  int count = 0;
  {
    uint8_t* __restrict flag = flags.data();
    const int32_t* __restrict band_r = band;
    flag[0] = 0;
    for (int i = 1; i + 1 < n; ++i) {
      const int32_t v = band_r[i];
      flag[i] = uint8_t(int(v >= threshold) & int(v >= band_r[i - 1]) & int(v > band_r[i + 1]));
    }
    for (int i = std::max(1, n - 1); i < padded; ++i) flag[i] = 0;
    int* __restrict out = candidates.data();
    static_assert(std::endian::native == std::endian::little, "flag k is byte k of the word");
    for (int base = 0; base < padded; base += 8) {
      uint64_t word;
      std::memcpy(&word, flag + base, 8);
      while (word) {  // byte k holds 0 or 1: its bit is 8k, little-endian
        out[count++] = base + std::countr_zero(word) / 8;
        word &= word - 1;
      }
    }
  }
  for (int c = 0; c < count; ++c) {
    const int i = candidates[c];
    const int32_t b = band[i];
    bool is_max = true;
    for (int j = std::max(0, i - a); j <= std::min(n - 1, i + a) && is_max; ++j) {
      is_max = band[j] <= b || j == i;
    }
    if (!is_max) continue;
    // Linear contrast, on both sides: a line stands above both flanks
    // (outside the inner box), a step edge only above one of them.
    int peak_value = samples.Value(i);
    for (int j = std::max(0, i - 1); j <= std::min(n - 1, i + 1); ++j) {
      peak_value = std::max(peak_value, samples.Value(j));
    }
    int left = 0, right = 0, left_count = 0, right_count = 0;
    for (int j = std::max(0, i - outer); j < i - a; ++j) left += samples.Value(j), ++left_count;
    for (int j = i + a + 1; j <= std::min(n - 1, i + outer); ++j)
      right += samples.Value(j), ++right_count;
    if (left_count == 0 || right_count == 0) continue;
    const double left_mean = double(left) / left_count, right_mean = double(right) / right_count;
    const double contrast = peak_value - std::max(left_mean, right_mean);
    if (contrast * samples.scale < o.min_contrast ||
        contrast < 0.5 * (peak_value - std::min(left_mean, right_mean))) {
      continue;
    }
    ++stats->candidate_peaks;
    // Step 3: signal-to-noise against the mean |response| in a 1D window
    // around the peak, leaving out the peak's own response (|j - i| <= b).
    int64_t noise = 0;
    const int lo_noise = std::max(0, i - noise_half), hi_noise = std::min(n - 1, i + noise_half);
    const int lo_core = std::max(lo_noise, i - outer), hi_core = std::min(hi_noise, i + outer);
    for (int j = lo_noise; j < lo_core; ++j) noise += std::abs(band[j]);
    for (int j = hi_core + 1; j <= hi_noise; ++j) noise += std::abs(band[j]);
    const int noise_count = (lo_core - lo_noise) + (hi_noise - hi_core);
    if (noise_count > 0 && b * static_cast<double>(noise_count) < o.min_snr * noise) continue;
    const double coarse = laser->offset + laser->stride * (i + skipped);
    if (o.cross_channel_suppression && laser->channel != kMono &&
        StrongerInOtherChannel(image, layout, row, *laser, coarse, b, bandpass)) {
      ++stats->suppressed_cross_channel;
      continue;
    }
    peaks->push_back({row, coarse, static_cast<float>(b / scale), laser->channel, i + skipped,
                      laser->offset, laser->stride});
  }
}

// Step 7's samples: around the raw maximum within the band-pass support.
// A thin line is undersampled by one colour of a mosaic, so a green line is
// read on the green channel at full resolution (the rows above and below
// fill the gaps).
void ReadPeakProfile(const cv::Mat& image, ColourLayout layout, const Peak& peak,
                     const DetectorOptions& o, PeakProfile* p) {
  const RowSamples samples =
      RowChannel(image, layout, peak.line, ScanChannel{peak.channel, peak.offset, peak.stride});
  const int n = samples.count;
  const int i = peak.sample;
  int k = i;
  if (i > 0 && samples.Value(i - 1) > samples.Value(k)) k = i - 1;
  if (i + 1 < n && samples.Value(i + 1) > samples.Value(k)) k = i + 1;
  const bool full_resolution_green = peak.stride == 2 && peak.channel == kGreen;
  const double sigma = full_resolution_green ? o.line_sigma_px : o.line_sigma_px / peak.stride;
  p->half_width = std::clamp(static_cast<int>(std::lround(sigma)), 1, 3);
  p->reference.clear();
  const bool albedo = o.albedo_channel >= 0 && o.albedo_channel != peak.channel &&
                      (full_resolution_green || layout == ColourLayout::kBgr);
  if (full_resolution_green) {
    const int outer = std::max(3, static_cast<int>(std::lround(4.0 * sigma)));
    const int centre = peak.offset + 2 * k;
    const int lo = std::max(0, centre - outer), hi = std::min(image.cols - 1, centre + outer);
    FullResolutionGreen(image, layout, peak.line, lo, hi - lo + 1, &p->laser);
    if (albedo) {
      FullResolutionChannel(image, layout, peak.line, o.albedo_channel, lo, hi - lo + 1,
                            &p->reference);
    }
    p->lo = lo, p->origin = 0, p->step = 1;
    p->best = centre - lo;
    for (int j = std::max(0, centre - lo - 1); j <= std::min(hi - lo, centre - lo + 1); ++j) {
      if (p->laser[j] > p->laser[p->best]) p->best = j;
    }
    return;
  }
  const int outer = std::max(std::max(1, static_cast<int>(std::lround(sigma))) + 2,
                             static_cast<int>(std::lround(4.0 * sigma)));
  const int lo = std::max(0, k - outer), hi = std::min(n - 1, k + outer);
  p->laser.resize(hi - lo + 1);
  for (int j = lo; j <= hi; ++j) p->laser[j - lo] = samples.Raw(j);
  if (albedo)
    FullResolutionChannel(image, layout, peak.line, o.albedo_channel, lo, hi - lo + 1,
                          &p->reference);
  p->lo = lo, p->origin = peak.offset, p->step = peak.stride;
  p->best = k - lo;
}

// How much of the line the albedo channel sees itself (colour filter
// crosstalk, e.g. a 532 nm laser in the red pixels): the median ratio of the
// line's height in the reference to its height in the laser channel, over
// peaks on an even albedo (both flanks of the reference alike) and not
// saturated. 0 with fewer than 8 such peaks.
double EstimateCrosstalk(const std::vector<PeakProfile>& profiles, size_t count) {
  std::vector<double> ratios;
  for (size_t i = 0; i < count; ++i) {
    const PeakProfile& p = profiles[i];
    if (p.reference.empty()) continue;
    const int n = static_cast<int>(p.laser.size());
    const int inner = p.half_width + 2;
    if (p.best - inner - 1 < 0 || p.best + inner + 1 >= n) continue;
    double left = 0.0, right = 0.0, laser_flank = 0.0;
    int left_count = 0, right_count = 0;
    for (int j = 0; j < n; ++j) {
      if (j < p.best - inner) left += p.reference[j], ++left_count, laser_flank += p.laser[j];
      if (j > p.best + inner) right += p.reference[j], ++right_count, laser_flank += p.laser[j];
    }
    left /= left_count, right /= right_count;
    laser_flank /= left_count + right_count;
    const double height = p.laser[p.best] - laser_flank;
    if (p.laser[p.best] >= kSaturation || height < 0.05) continue;
    if (std::abs(left - right) > 0.15 * std::max(left, right)) continue;
    ratios.push_back((p.reference[p.best] - 0.5 * (left + right)) / height);
  }
  if (ratios.size() < 8) return 0.0;
  return std::max(0.0, Median(ratios));
}

// See DetectorOptions::albedo_channel: whether the albedo changes by more
// than max_albedo_step within the fit's support around the peak, as the
// reference shows it once the line's own light (`crosstalk`) is taken out.
bool OnAlbedoEdge(const DetectorOptions& o, double crosstalk, const PeakProfile& p) {
  if (p.reference.empty()) return false;
  const int n = static_cast<int>(p.laser.size());
  const int first = std::max(0, p.best - p.half_width - 1);
  const int last = std::min(n - 1, p.best + p.half_width + 1);
  // The flood must light the surface beside the line (not so in a
  // difference image, or in the dark).
  float flank = 0.0f;
  for (const auto& [from, to] : {std::pair{0, first}, std::pair{last + 1, n}}) {
    if (to <= from) continue;
    float sum = 0.0f;
    for (int j = from; j < to; ++j) sum += p.reference[j];
    flank = std::max(flank, sum / (to - from));
  }
  if (!(flank >= o.min_albedo_reference)) return false;
  float darkest = std::numeric_limits<float>::infinity(), brightest = 0.0f;
  for (int j = first; j <= last; ++j) {
    const float albedo =
        std::max(0.0f, p.reference[j] - static_cast<float>(crosstalk) * p.laser[j]);
    darkest = std::min(darkest, albedo);
    brightest = std::max(brightest, albedo);
  }
  constexpr float kOneGreyLevel = 1.0f / 255.0f;  // a black side is not infinitely dark
  return brightest > o.max_albedo_step * std::max(darkest, kOneGreyLevel);
}

// Step 7, run only on the selected peaks: Gaussian fit on the raw samples
// around the raw maximum, above the darkest sample within the band-pass
// support. Full-resolution position across the line.
double RefinePeak(const PeakProfile& p) {
  const float background = *std::min_element(p.laser.begin(), p.laser.end());
  const double position =
      p.lo + GaussianPeakPosition(p.laser.data(), static_cast<int>(p.laser.size()), p.best,
                                  p.half_width, background, kSaturation);
  return p.origin + p.step * position;
}

// Baselines on one scan line: per-line argmax, or centre of gravity of the
// samples above a fraction of the maximum around it. They read the raw
// samples in place, as a plain implementation would.
template <typename Pixel>
void BaselineOnRow(const Pixel* data, const RowSamples& samples, const ScanChannel& laser, int row,
                   const DetectorOptions& o, std::vector<Peak>* peaks) {
  const int n = samples.count;
  int k = 0;
  Pixel best = data[0];
  for (int i = 1; i < n; ++i) {
    const Pixel value = data[i * samples.step];
    if (value > best) best = value, k = i;
  }
  const float peak = best * samples.scale;
  if (peak < o.min_peak_intensity) return;
  double position = k;
  if (o.method == Method::kCentreOfGravity) {
    const float threshold = static_cast<float>(o.cog_threshold) * best;
    int left = k, right = k;
    while (left > 0 && data[(left - 1) * samples.step] >= threshold) --left;
    while (right + 1 < n && data[(right + 1) * samples.step] >= threshold) ++right;
    double sum = 0.0, weighted = 0.0;
    for (int i = left; i <= right; ++i) {
      const double w = data[i * samples.step] - threshold;
      sum += w;
      weighted += w * i;
    }
    if (sum > 0.0) position = weighted / sum;
  }
  peaks->push_back({row, laser.offset + laser.stride * position, peak, laser.channel, k,
                    laser.offset, laser.stride});
}

void BaselineLinePeak(const cv::Mat& image, ColourLayout layout, int row, const DetectorOptions& o,
                      std::vector<Peak>* peaks) {
  const auto channels = ChannelsOnRow(layout, row);
  const ScanChannel* laser = FindLaserChannel(channels, o.laser_channel);
  if (!laser) return;
  const RowSamples samples = RowChannel(image, layout, row, *laser);
  if (samples.data8)
    BaselineOnRow(samples.data8 + samples.first, samples, *laser, row, o, peaks);
  else
    BaselineOnRow(samples.data16 + samples.first, samples, *laser, row, o, peaks);
}

}  // namespace

Detection DetectLaserLine(const cv::Mat& image_in, ColourLayout layout_in,
                          const DetectorOptions& options) {
  options.Check();
  UWS_CHECK(!image_in.empty(), "laser detection: empty image");
  UWS_CHECK(image_in.depth() == CV_8U || image_in.depth() == CV_16U,
            "laser detection: images must be 8- or 16-bit");
  UWS_CHECK(image_in.channels() == (layout_in == ColourLayout::kBgr ? 3 : 1),
            "laser detection: image has ", image_in.channels(), " channels, layout expects ",
            layout_in == ColourLayout::kBgr ? 3 : 1);
  // Scanning columns = scanning rows of the transposed image.
  cv::Mat image = image_in;
  ColourLayout layout = layout_in;
  if (!options.scan_rows) {
    cv::transpose(image_in, image);
    layout = TransposedLayout(layout_in);
  }
  DetectorOptions o = options;
  if (layout == ColourLayout::kMono) o.laser_channel = kMono;

  Detection detection;
  std::vector<Peak> peaks;
  Scratch scratch;
  std::vector<std::pair<int, int>> selected;
  if (o.method == Method::kThesis) {
    for (int row = 0; row < image.rows; ++row) {
      FindLinePeaks(image, layout, row, o, &scratch, &peaks, &detection.stats);
    }
    if (o.keep_candidates) {
      detection.candidates.reserve(peaks.size());
      for (const Peak& p : peaks)
        detection.candidates.push_back(ToLaserPoint(p, options.scan_rows));
    }
    std::vector<Peak> all_peaks;
    if (o.exclude_candidate) {
      all_peaks = peaks;
      detection.stats.excluded_candidates = ExcludePeaks(o.exclude_candidate, &peaks);
    }
    std::vector<Segment> segments;
    const auto select = [&] {
      segments = GroupPeaks(peaks, o.max_jump_px, o.max_gap_lines);
      DropOffColourSegments(image, layout, o, peaks, &segments, &detection.stats);
      selected = SelectSegments(peaks, segments, image.rows, o.min_segment_lines,
                                o.min_relative_strength, o.line_continuity_px);
    };
    select();
    const double excluded = detection.stats.excluded_candidates;
    if (excluded > 0 && excluded > o.exclude_restore_fraction * (excluded + selected.size())) {
      // Nearly the whole line would go: the sweep stalled or the scene is
      // degenerate; keep what the frame shows.
      peaks = std::move(all_peaks);
      detection.stats.excluded_candidates =
          o.exclude_candidate_on_restore ? ExcludePeaks(o.exclude_candidate_on_restore, &peaks) : 0;
      select();
      detection.stats.exclusion_restored = true;
    }
    detection.stats.segments = static_cast<int>(segments.size());
    auto& profiles = scratch.profiles;
    profiles.resize(std::max(profiles.size(), selected.size()));
    for (size_t j = 0; j < selected.size(); ++j) {
      ReadPeakProfile(image, layout, peaks[selected[j].first], o, &profiles[j]);
    }
    detection.stats.albedo_crosstalk =
        o.albedo_channel >= 0 ? EstimateCrosstalk(profiles, selected.size()) : 0.0;
    size_t kept = 0;
    for (size_t j = 0; j < selected.size(); ++j) {
      Peak& peak = peaks[selected[j].first];
      peak.position = RefinePeak(profiles[j]);
      if (OnAlbedoEdge(o, detection.stats.albedo_crosstalk, profiles[j])) {
        LaserPoint point = ToLaserPoint(peak, options.scan_rows);
        point.segment = selected[j].second;
        detection.albedo_edge_points.push_back(point);
        continue;
      }
      selected[kept++] = selected[j];
    }
    selected.resize(kept);
    detection.stats.albedo_edge_points = static_cast<int>(detection.albedo_edge_points.size());
    std::vector<bool> used(segments.size(), false);
    for (const auto& [peak, segment] : selected) used[segment] = true;
    detection.stats.selected_segments =
        static_cast<int>(std::count(used.begin(), used.end(), true));
  } else {
    for (int row = 0; row < image.rows; ++row) {
      BaselineLinePeak(image, layout, row, o, &peaks);
    }
    for (size_t i = 0; i < peaks.size(); ++i) selected.emplace_back(static_cast<int>(i), 0);
    detection.stats.candidate_peaks = static_cast<int>(peaks.size());
  }

  detection.points.reserve(selected.size());
  for (const auto& [index, segment] : selected) {
    LaserPoint point = ToLaserPoint(peaks[index], options.scan_rows);
    point.segment = segment;
    detection.points.push_back(point);
  }
  if (options.make_mask) {
    detection.mask = cv::Mat::zeros(image_in.size(), CV_8U);
    const int half = static_cast<int>(std::ceil(options.mask_sigmas * options.line_sigma_px));
    const auto mask_point = [&](const LaserPoint& point) {
      const double along = options.scan_rows ? point.u : point.v;
      const int line = static_cast<int>(options.scan_rows ? point.v : point.u);
      const int limit = options.scan_rows ? image_in.cols : image_in.rows;
      const int lo = std::max(0, static_cast<int>(std::floor(along)) - half);
      const int hi = std::min(limit - 1, static_cast<int>(std::ceil(along)) + half);
      for (int i = lo; i <= hi; ++i) {
        if (options.scan_rows)
          detection.mask.at<uint8_t>(line, i) = 255;
        else
          detection.mask.at<uint8_t>(i, line) = 255;
      }
    };
    for (const auto& point : detection.points) mask_point(point);
    for (const auto& point : detection.albedo_edge_points) mask_point(point);
  }
  return detection;
}

int OtherColourOfTheLine(const cv::Mat& image, ColourLayout layout, const DetectorOptions& options,
                         size_t found) {
  const int scan_lines = options.scan_rows ? image.rows : image.cols;
  if (layout == ColourLayout::kMono || found >= 0.1 * scan_lines) return -1;
  for (int channel : {kRed, kGreen, kBlue}) {
    if (channel == options.laser_channel) continue;
    DetectorOptions other;
    other.scan_rows = options.scan_rows;
    other.laser_channel = channel;
    if (DetectLaserLine(image, layout, other).points.size() >= 0.3 * scan_lines) return channel;
  }
  return -1;
}

std::string LaserColourWarning(int seen, int expected, double wavelength_nm) {
  std::string text = std::string("the laser line shows in ") + ChannelName(seen) + ", not in " +
                     ChannelName(expected);
  if (wavelength_nm > 0.0) {
    char nm[32];
    std::snprintf(nm, sizeof(nm), "%g", wavelength_nm);
    return text + ", the colour of its " + nm +
           " nm in rig.yaml: set the laser's wavelength_nm to its own (about 450 for a blue "
           "laser, 520-532 for a green one, 640-660 for a red one)";
  }
  return text + ", the colour looked in: give --channel " + ChannelName(seen);
}

}  // namespace uwscan::laser
