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
  bool cross_channel_suppression = true;  // §5.5: drop peaks stronger in another channel
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
};

struct Detection {
  std::vector<LaserPoint> points;  // at most one per scan line
  // With keep_candidates: every candidate peak before exclusion and
  // selection (coarse positions, strength), for laser::SweepFilter.
  std::vector<LaserPoint> candidates;
  cv::Mat mask;                    // CV_8U, 255 where the line is; empty if !make_mask
  DetectionStats stats;
};

// Throws uwscan::Error for an unsupported image type.
Detection DetectLaserLine(const cv::Mat& image, ColourLayout layout,
                          const DetectorOptions& options);

}  // namespace uwscan::laser
