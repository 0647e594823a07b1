// Laser line detection (thesis §5.3, §5.5): finds the projected laser line
// in a camera frame with sub-pixel precision, per scan line across the line.
//
// Input: 8/16-bit mono, 3-channel BGR (OpenCV order), or a raw Bayer mosaic
// (single channel, pattern named). Output: sub-pixel points with channel,
// strength and segment id, plus a mask of the pixels the line covers.
#pragma once

#include <functional>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

namespace uwscan::laser {

enum class Method { kThesis, kCentreOfGravity, kArgmax };
std::optional<Method> MethodFromName(const std::string& name);
const char* MethodName(Method method);

// Colour channels in RGB order (not OpenCV's BGR storage order).
enum Channel : int { kRed = 0, kGreen = 1, kBlue = 2, kMono = 3 };
const char* ChannelName(int channel);
// The camera channel that sees a laser of this wavelength best.
int ChannelForWavelength(double wavelength_nm);
// "red", "green", "blue" -> the channel; anything else -> -1.
int ChannelFromName(const std::string& name);
// The channel that sees the scene's albedo beside a laser in `laser_channel`
// (DetectorOptions::albedo_channel): red for a green laser (the thesis's red
// LEDs), green for a red or blue one, -1 for mono.
int AlbedoChannelFor(int laser_channel);
// The colour that is neither the laser's nor its albedo channel's
// (DetectorOptions::min_signature_share): blue for a green or red laser,
// red for a blue one; -1 for mono.
int SignatureChannelFor(int laser_channel);

// How the input image stores colour.
enum class ColourLayout { kMono, kBgr, kBayerRggb, kBayerBggr, kBayerGrbg, kBayerGbrg };
// From rig.yaml's `bayer` and the image's channel count.
ColourLayout LayoutFor(const std::string& bayer, int image_channels);

struct DetectorOptions {
  Method method = Method::kThesis;
  // Scan across the line along image rows (for a roughly vertical line) or
  // along columns (roughly horizontal line).
  bool scan_rows = true;
  int laser_channel = kGreen;  // ignored for mono input
  double line_sigma_px = 1.5;  // expected Gaussian sigma of the line across it
  static constexpr double kMinLineSigmaPx = 0.2, kMaxLineSigmaPx = 50.0;  // exclusive bounds
  // Thesis method.
  double min_snr = 3.0;        // band-pass response / mean |response| around it
  double min_strength = 0.02;  // band-pass response in log-intensity units (0..1)
  // The log scaling lifts dark noise; a peak must also stand this far above
  // the darkest sample around it in linear intensity (fraction of full scale).
  double min_contrast = 0.02;
  int noise_half_window_px = 24;  // 1D window for the noise mean
  int max_jump_px = 2;            // connectivity: max shift between consecutive scan lines
  int max_gap_lines = 2;          // scan lines a segment may skip
  int min_segment_lines = 6;      // shorter segments are noise (marine snow, specks)
  // Further segments must reach this share of the best segment's mean
  // strength: the line is one light source, texture stripes are fainter.
  double min_relative_strength = 0.3;
  // After the best segment, those continuing the line taken so far (an end
  // within this, plus a pixel per scan line between) win their scan lines
  // before the others: dark texture breaks the line into short pieces, and a
  // bright blob beside one (marine snow lit by the floods) would otherwise
  // take its lines (SelectSegments). 0: by score alone.
  double line_continuity_px = 4.0;
  bool cross_channel_suppression = true;  // §5.5: drop peaks stronger in another channel
  // Colour signature (§5.5's colour separation, one step on): light of one
  // wavelength reaches the three colours of the camera's filters in fixed
  // shares, whatever the surface, the water or the range, and a flood's
  // broad spectrum does not (a red LED gives no blue). In the third colour,
  // neither the laser's nor the albedo's (blue beside a green laser and red
  // LEDs), a segment that shows less than this share of what the frame's
  // line gives it for as much laser light is not the laser: marine snow lit
  // by the floods, bright enough to clip red and show in green through the
  // filters' crosstalk, which the cross-channel test cannot judge (red is
  // clipped). Judged only where the line's share would stand well out of
  // the noise: at least min_signature_height (of full scale, summed across
  // the line: some 13 grey levels of 255) per peak on average. 0: off; also
  // off for mono images.
  double min_signature_share = 0.15;
  double min_signature_height = 0.05;
  // Albedo edges (thesis method): the line's image is the laser's irradiance
  // times the surface albedo, so where the line runs along an albedo edge (a
  // checkerboard square's side) the fit is pulled towards the bright side by
  // up to a pixel (several mm at 2 m). A channel lit by a flood (red LED
  // beside a green laser) sees the same albedo: a detection is dropped where
  // that channel, less the line's own crosstalk, changes by more than
  // max_albedo_step within the fit's support. Dividing by the albedo instead
  // was tried: at a 20:1 edge it amplifies the dark side's noise and the
  // edge's 2-px sampling in a mosaic, and the fit fails. -1: off (also for a
  // red or blue laser in a Bayer mosaic). Not judged where the reference is
  // darker than min_albedo_reference beside the line (e.g. in a difference
  // image).
  int albedo_channel = -1;
  double max_albedo_step = 3.0;
  double min_albedo_reference = 0.03;  // reference beside the line, of full scale
  // Baselines: fraction of the scan line's maximum above which pixels count.
  double cog_threshold = 0.5;
  double min_peak_intensity = 0.08;  // of full scale, for the baselines
  // Thesis method: candidate peaks for which this returns true (position
  // across the line in full-resolution px, scan line index) are dropped
  // before the segments are formed (laser::SweepFilter: scene stripes) —
  // unless they outnumber the selected line points by far (more than this
  // share of both together): then the frame is detected without it.
  std::function<bool(double position, int line)> exclude_candidate;
  double exclude_restore_fraction = 0.8;
  // On restoring, candidates this stricter test still flags stay excluded
  // (empty: none); e.g. only what stands exactly where a stripe stood.
  std::function<bool(double position, int line)> exclude_candidate_on_restore;
  bool keep_candidates = false;  // fill Detection::candidates
  // Thesis method: where the line was (the frame before's detection, say),
  // per scan line the interval of positions across the line
  // (full-resolution px; NaN where none). Such a scan line is searched
  // only within line_window_px of its interval, the others whole; empty:
  // every scan line whole. The window must hold the line's motion from
  // the prior plus the band-pass and noise supports (noise_half_window_px
  // and 4 line sigmas) for a peak inside to be found as on the whole line.
  std::vector<std::pair<float, float>> line_prior;
  int line_window_px = 48;
  // Mask: pixels within this many sigmas of a detection are masked.
  double mask_sigmas = 3.0;
  bool make_mask = true;

  void Check() const;
};

struct LaserPoint {
  double u = 0.0;  // sub-pixel column (OpenCV convention)
  double v = 0.0;  // row
  int channel = kGreen;
  float strength = 0.0f;  // band-pass response (thesis) or normalised intensity
  int segment = -1;
};

struct DetectionStats {
  int candidate_peaks = 0;
  int segments = 0;
  int selected_segments = 0;
  int suppressed_cross_channel = 0;
  int excluded_candidates = 0;      // by exclude_candidate (or the restore test)
  bool exclusion_restored = false;  // nearly all would have gone: kept
  double albedo_crosstalk = 0.0;    // the line's share seen in the albedo channel
  int albedo_edge_points = 0;       // dropped on an albedo edge
  // DetectorOptions::min_signature_share: the line's share in the third
  // colour (0: not measured), and the segments and peaks dropped for
  // showing too little of it.
  double colour_signature = 0.0;
  int off_colour_segments = 0;
  int off_colour_peaks = 0;
};

struct Detection {
  std::vector<LaserPoint> points;  // at most one per scan line
  // With keep_candidates: every candidate peak before exclusion and
  // selection (coarse positions, strength), for laser::SweepFilter.
  std::vector<LaserPoint> candidates;
  // Line points dropped on an albedo edge (DetectorOptions::albedo_channel):
  // biased, so not in `points`, but masked.
  std::vector<LaserPoint> albedo_edge_points;
  cv::Mat mask;  // CV_8U, 255 where the line is; empty if !make_mask
  DetectionStats stats;
};

// Throws uwscan::Error for an unsupported image type.
Detection DetectLaserLine(const cv::Mat& image, ColourLayout layout,
                          const DetectorOptions& options);

// Where `found` points of a colour image's line in options.laser_channel
// are under a tenth of its scan lines: the other colour (kRed, kGreen or
// kBlue) that shows a line on 30 % of them or more (a laser of another
// colour than the one looked in); -1 if none, or for a mono image.
int OtherColourOfTheLine(const cv::Mat& image, ColourLayout layout, const DetectorOptions& options,
                         size_t found);
// What to say when the line shows in `seen`, not in `expected`: the colour
// of rig.yaml's `wavelength_nm` (> 0), or else the one looked in.
std::string LaserColourWarning(int seen, int expected, double wavelength_nm);

}  // namespace uwscan::laser
