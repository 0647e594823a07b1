#include "uwscan/laser/detector.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "uwscan/laser/scanline.h"
#include "uwscan/laser/segments.h"
#include "uwscan/laser/subpixel.h"
#include "uwscan/laser/synthetic_line.h"
#include "uwscan/util/error.h"

namespace uwscan::laser {
namespace {

struct Score {
  double rms = 0.0;           // px, over true points found within 1 px
  double completeness = 0.0;  // share of true rows found within 1 px
  double outliers = 0.0;      // share of detections > 2 px from the truth
  int detections = 0;
};

Score Evaluate(const Detection& detection, const SyntheticLine& line, bool scan_rows = true) {
  std::map<int, double> truth;
  for (const auto& p : line.truth)
    truth[static_cast<int>(scan_rows ? p.y : p.x)] = scan_rows ? p.x : p.y;
  Score score;
  double sum = 0.0;
  int found = 0, outliers = 0;
  for (const auto& p : detection.points) {
    const int key = static_cast<int>(scan_rows ? p.v : p.u);
    const double along = scan_rows ? p.u : p.v;
    const auto it = truth.find(key);
    const double error = it == truth.end() ? 1e9 : std::abs(along - it->second);
    if (error > 2.0) ++outliers;
    if (error <= 1.0) {
      sum += error * error;
      ++found;
    }
  }
  score.detections = static_cast<int>(detection.points.size());
  score.rms = found ? std::sqrt(sum / found) : 1e9;
  score.completeness = truth.empty() ? 1.0 : static_cast<double>(found) / truth.size();
  score.outliers = score.detections ? static_cast<double>(outliers) / score.detections : 0.0;
  return score;
}

TEST(LaserDetector, SubPixelOnCleanMonoLine) {
  SyntheticLineOptions o;
  o.noise = 0.0;
  o.texture = 0.0;
  o.sixteen_bit = true;  // no quantisation: isolates the estimator
  const SyntheticLine line = RenderSyntheticLine(o);
  const Detection detection = DetectLaserLine(line.image, ColourLayout::kMono, DetectorOptions{});
  const Score score = Evaluate(detection, line);
  EXPECT_LT(score.rms, 0.01);
  EXPECT_GT(score.completeness, 0.99);
  EXPECT_EQ(score.outliers, 0.0);
}

TEST(LaserDetector, NoisyTexturedMono8Bit) {
  SyntheticLineOptions o;
  o.curvature = 0.001;
  const SyntheticLine line = RenderSyntheticLine(o);
  const Detection detection = DetectLaserLine(line.image, ColourLayout::kMono, DetectorOptions{});
  const Score score = Evaluate(detection, line);
  EXPECT_LT(score.rms, 0.1);
  EXPECT_GT(score.completeness, 0.97);
  EXPECT_LT(score.outliers, 0.01);
  // The mask covers every detection.
  for (const auto& p : detection.points) {
    EXPECT_EQ(detection.mask.at<uint8_t>(static_cast<int>(p.v), static_cast<int>(std::lround(p.u))),
              255);
  }
  EXPECT_GT(cv::countNonZero(detection.mask), 5 * static_cast<int>(detection.points.size()));
}

TEST(LaserDetector, RawBayerGreenLaserUnderRedLed) {
  for (const auto layout : {ColourLayout::kBayerRggb, ColourLayout::kBayerGbrg}) {
    SyntheticLineOptions o;
    o.layout = layout;
    o.sigma_px = 2.0;
    const SyntheticLine line = RenderSyntheticLine(o);
    DetectorOptions options;
    options.line_sigma_px = 2.0;
    const Detection detection = DetectLaserLine(line.image, layout, options);
    const Score score = Evaluate(detection, line);
    EXPECT_LT(score.rms, 0.15);
    EXPECT_GT(score.completeness, 0.95);
    EXPECT_LT(score.outliers, 0.01);
    for (const auto& p : detection.points) EXPECT_EQ(p.channel, kGreen);
  }
}

// A line running along an albedo edge (a checkerboard square's side) is
// pulled towards the bright side by the edge. The red LED shows the edge:
// those detections are dropped (but masked); an edge beyond the fit's
// support leaves the line alone. The line's own light in the red pixels
// (crosstalk) is measured on the frame, not mistaken for an edge.
TEST(LaserDetector, DetectionsOnAnAlbedoEdgeAreDropped) {
  for (const auto layout : {ColourLayout::kBayerRggb, ColourLayout::kBgr}) {
    SyntheticLineOptions o;
    o.layout = layout;
    o.albedo_edge = true;
    o.albedo_edge_offset_px = 0.7;
    const SyntheticLine line = RenderSyntheticLine(o);
    DetectorOptions options;
    const Detection biased = DetectLaserLine(line.image, layout, options);
    ASSERT_GT(biased.points.size(), 200u);
    double mean_error = 0.0;
    for (const auto& p : biased.points)
      mean_error += p.u - (o.u0 + o.slope * (p.v - o.height / 2.0));
    mean_error /= biased.points.size();
    EXPECT_LT(mean_error, -0.3);  // towards the bright side

    options.albedo_channel = kRed;
    const Detection dropped = DetectLaserLine(line.image, layout, options);
    EXPECT_GT(dropped.stats.albedo_edge_points, 0.95 * biased.points.size());
    EXPECT_LT(dropped.points.size(), 0.05 * biased.points.size());
    for (const auto& p : dropped.albedo_edge_points) {
      EXPECT_EQ(dropped.mask.at<uint8_t>(static_cast<int>(p.v), static_cast<int>(std::lround(p.u))),
                255);
    }

    o.albedo_edge_offset_px = 10.0;
    const SyntheticLine far = RenderSyntheticLine(o);
    const Detection kept = DetectLaserLine(far.image, layout, options);
    EXPECT_EQ(kept.stats.albedo_edge_points, 0);
    const Score score = Evaluate(kept, far);
    EXPECT_GT(score.completeness, 0.95);
    EXPECT_LT(score.rms, 0.15);
    EXPECT_NEAR(kept.stats.albedo_crosstalk, o.laser_colour[kRed] / o.laser_colour[kGreen], 0.03);
  }
}

// A painted stripe lit by the LED looks like a line but has the LED's
// colour; cross-channel suppression (§5.5) keeps it out, and the real line
// wins.
TEST(LaserDetector, PaintedStripeIsNotTakenForTheLaser) {
  for (const auto layout : {ColourLayout::kBgr, ColourLayout::kBayerRggb}) {
    SyntheticLineOptions o;
    o.layout = layout;
    o.stripe = true;
    o.stripe_amplitude = 1.2;  // brighter than the laser in the raw image
    const SyntheticLine line = RenderSyntheticLine(o);
    const Detection detection = DetectLaserLine(line.image, layout, DetectorOptions{});
    const Score score = Evaluate(detection, line);
    EXPECT_GT(score.completeness, 0.95);
    EXPECT_LT(score.outliers, 0.01);
    EXPECT_GT(detection.stats.suppressed_cross_channel, 0);
  }
}

// A stripe that a mono camera cannot tell from the line by colour, brighter
// than it: excluded as a candidate (laser::SweepFilter's verdict), the laser
// wins every scan line; when nearly everything would be excluded, the frame
// is detected as it is.
TEST(LaserDetector, ExcludedCandidatesLetTheWeakerLineWin) {
  SyntheticLineOptions o;
  o.stripe = true;
  o.amplitude = 0.3;
  o.stripe_amplitude = 0.6;
  const SyntheticLine line = RenderSyntheticLine(o);
  DetectorOptions options;
  options.keep_candidates = true;
  const Detection plain = DetectLaserLine(line.image, ColourLayout::kMono, options);
  EXPECT_GT(Evaluate(plain, line).outliers, 0.5);  // the stripe wins
  EXPECT_GE(plain.candidates.size(), 2 * line.truth.size());
  const auto stripe_u = [&](int v) { return o.stripe_u0 + o.stripe_slope * (v - o.height / 2.0); };
  options.exclude_candidate = [&](double position, int row) {
    return std::abs(position - stripe_u(row)) < 3.0;
  };
  const Detection excluded = DetectLaserLine(line.image, ColourLayout::kMono, options);
  const Score score = Evaluate(excluded, line);
  EXPECT_GT(score.completeness, 0.95);
  EXPECT_LT(score.outliers, 0.01);
  EXPECT_GE(excluded.stats.excluded_candidates, o.height * 9 / 10);
  EXPECT_FALSE(excluded.stats.exclusion_restored);
  // Everything excluded: restored, as without exclusion.
  options.exclude_candidate = [](double, int) { return true; };
  const Detection restored = DetectLaserLine(line.image, ColourLayout::kMono, options);
  EXPECT_TRUE(restored.stats.exclusion_restored);
  EXPECT_EQ(restored.stats.excluded_candidates, 0);
  EXPECT_EQ(restored.points.size(), plain.points.size());
}

// A prior of the line (the frame before's) limits each scan line's search
// to a window around it: a brighter stripe outside it is not seen; a scan
// line without a prior is searched whole; and a line inside the window is
// found exactly as on the whole scan line (mono and raw Bayer).
TEST(LaserDetector, LinePriorSearchesAWindowAroundIt) {
  SyntheticLineOptions o;
  o.stripe = true;
  o.amplitude = 0.3;
  o.stripe_amplitude = 0.6;  // 90 px from the line, brighter: wins a whole scan line
  const SyntheticLine line = RenderSyntheticLine(o);
  DetectorOptions options;
  const Detection whole = DetectLaserLine(line.image, ColourLayout::kMono, options);
  EXPECT_GT(Evaluate(whole, line).outliers, 0.5);
  // The line 4 px from where the prior has it, upper half only.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  options.line_prior.assign(o.height, {nan, nan});
  for (const auto& p : line.truth) {
    if (p.y < o.height / 2) options.line_prior[static_cast<int>(p.y)] = {p.x + 4, p.x + 4};
  }
  options.keep_candidates = true;
  const Detection windowed = DetectLaserLine(line.image, ColourLayout::kMono, options);
  const auto stripe_u = [&](double v) {
    return o.stripe_u0 + o.stripe_slope * (v - o.height / 2.0);
  };
  int on_line = 0;
  for (const auto& p : windowed.points) {
    if (p.v >= o.height / 2) continue;
    EXPECT_LT(std::abs(p.u - line.truth[static_cast<int>(p.v)].x), 1.0) << "row " << p.v;
    ++on_line;
  }
  EXPECT_GT(on_line, o.height / 2 * 95 / 100);
  // The stripe is a candidate only where the scan line was searched whole.
  int stripe_above = 0, stripe_below = 0;
  for (const auto& c : windowed.candidates) {
    if (std::abs(c.u - stripe_u(c.v)) > 2.0) continue;
    (c.v < o.height / 2 ? stripe_above : stripe_below)++;
  }
  EXPECT_EQ(stripe_above, 0);
  EXPECT_GT(stripe_below, o.height / 2 * 90 / 100);
  // Too narrow a window for the line's supports: the line is not found there.
  options.line_window_px = 2;
  options.keep_candidates = false;
  const Detection narrow = DetectLaserLine(line.image, ColourLayout::kMono, options);
  EXPECT_LT(std::count_if(narrow.points.begin(), narrow.points.end(),
                          [&](const LaserPoint& p) { return p.v < o.height / 2; }),
            o.height / 10);

  // A prior off the image: nothing is searched on its scan lines.
  options.line_window_px = 48;
  for (auto& [from, to] : options.line_prior) from = to = -500.0f;
  EXPECT_TRUE(DetectLaserLine(line.image, ColourLayout::kMono, options).points.empty());

  for (const auto layout : {ColourLayout::kMono, ColourLayout::kBayerRggb}) {
    SyntheticLineOptions clean;
    clean.layout = layout;
    clean.slope = 0.4;
    const SyntheticLine plain = RenderSyntheticLine(clean);
    DetectorOptions prior;
    const Detection all = DetectLaserLine(plain.image, layout, prior);
    ASSERT_GT(all.points.size(), plain.truth.size() * 95 / 100);
    prior.line_prior.assign(clean.height, {nan, nan});
    for (const auto& p : plain.truth) prior.line_prior[static_cast<int>(p.y)] = {p.x - 6, p.x + 3};
    const Detection near = DetectLaserLine(plain.image, layout, prior);
    ASSERT_EQ(near.points.size(), all.points.size());
    for (size_t i = 0; i < all.points.size(); ++i) {
      EXPECT_EQ(near.points[i].u, all.points[i].u);
      EXPECT_EQ(near.points[i].v, all.points[i].v);
      EXPECT_EQ(near.points[i].strength, all.points[i].strength);
    }
  }
}

TEST(LaserDetector, FrameWithoutLaserGivesNoPoints) {
  SyntheticLineOptions o;
  o.layout = ColourLayout::kBayerRggb;
  o.first_row = 1 << 30;  // no lit row
  o.stripe = true;
  const SyntheticLine line = RenderSyntheticLine(o);
  ASSERT_TRUE(line.truth.empty());
  const Detection detection =
      DetectLaserLine(line.image, ColourLayout::kBayerRggb, DetectorOptions{});
  EXPECT_TRUE(detection.points.empty()) << detection.points.size();
  EXPECT_EQ(cv::countNonZero(detection.mask), 0);
}

TEST(LaserDetector, PartialLineAndHorizontalScan) {
  SyntheticLineOptions o;
  o.first_row = 60;
  o.last_row = 180;
  const SyntheticLine line = RenderSyntheticLine(o);
  const Detection rows = DetectLaserLine(line.image, ColourLayout::kMono, DetectorOptions{});
  const Score score = Evaluate(rows, line);
  EXPECT_GT(score.completeness, 0.97);
  EXPECT_LT(score.outliers, 0.01);
  // The same image transposed, scanned along columns, gives the same points.
  cv::Mat transposed;
  cv::transpose(line.image, transposed);
  DetectorOptions columns;
  columns.scan_rows = false;
  const Detection cols = DetectLaserLine(transposed, ColourLayout::kMono, columns);
  ASSERT_EQ(cols.points.size(), rows.points.size());
  for (size_t i = 0; i < rows.points.size(); ++i) {
    EXPECT_DOUBLE_EQ(cols.points[i].u, rows.points[i].v);
    EXPECT_DOUBLE_EQ(cols.points[i].v, rows.points[i].u);
  }
}

TEST(LaserDetector, BaselinesRunAndAreLessPrecise) {
  SyntheticLineOptions o;
  const SyntheticLine line = RenderSyntheticLine(o);
  DetectorOptions options;
  const Score thesis = Evaluate(DetectLaserLine(line.image, ColourLayout::kMono, options), line);
  options.method = Method::kArgmax;
  const Score argmax = Evaluate(DetectLaserLine(line.image, ColourLayout::kMono, options), line);
  options.method = Method::kCentreOfGravity;
  const Score cog = Evaluate(DetectLaserLine(line.image, ColourLayout::kMono, options), line);
  EXPECT_GT(argmax.completeness, 0.9);
  EXPECT_GT(cog.completeness, 0.9);
  EXPECT_GT(argmax.rms, 0.2);  // integer positions: ~0.29 px
  EXPECT_LT(thesis.rms, cog.rms);
}

TEST(LaserDetector, SaturatedLineUsesFlankMidpoint) {
  // Symmetric flanks around 4.5.
  const float symmetric[9] = {0.1f, 0.2f, 0.6f, 1.0f, 1.0f, 1.0f, 1.0f, 0.6f, 0.2f};
  EXPECT_NEAR(GaussianPeakPosition(symmetric, 9, 4, 2, 0.1f), 4.5, 1e-9);
  // A clipped Gaussian at 10.3 (sigma 1.2, peak 3x the clip level).
  float clipped[21];
  for (int i = 0; i < 21; ++i) {
    clipped[i] = std::min(
        1.0f, static_cast<float>(0.05 + 3.0 * std::exp(-0.5 * std::pow((i - 10.3) / 1.2, 2))));
  }
  EXPECT_NEAR(GaussianPeakPosition(clipped, 21, 10, 2, 0.05f), 10.3, 0.05);
}

TEST(LaserDetector, GaussianFitIsExactOnSampledGaussian) {
  for (double centre : {10.0, 10.3, 9.55}) {
    float samples[21];
    for (int i = 0; i < 21; ++i) {
      samples[i] =
          static_cast<float>(0.05 + 0.8 * std::exp(-0.5 * std::pow((i - centre) / 2.0, 2)));
    }
    const int k = static_cast<int>(std::lround(centre));
    EXPECT_NEAR(GaussianPeakPosition(samples, 21, k, 2, 0.05f), centre, 1e-4);
  }
}

TEST(LaserSegments, ScoreFollowsEquation51AndSelectionAvoidsOverlap) {
  std::vector<Peak> peaks;
  for (int line = 0; line < 10; ++line) {
    peaks.push_back({line, 50.0 + 0.5 * line, 0.1f, kGreen});                 // long, strong
    if (line >= 3 && line < 7) peaks.push_back({line, 100.0, 0.5f, kGreen});  // short, bright
  }
  std::sort(peaks.begin(), peaks.end(),
            [](const Peak& a, const Peak& b) { return a.line < b.line; });
  const auto segments = GroupPeaks(peaks, 2, 1);
  ASSERT_EQ(segments.size(), 2u);
  for (const auto& s : segments) {
    double sum = 0.0;
    for (int p : s.peaks) sum += peaks[p].strength;
    EXPECT_DOUBLE_EQ(s.score, s.peaks.size() + 1e4 * sum);
  }
  // The short bright segment scores 4 + 2e4, the long one 10 + 1e4: the bright
  // one is taken on its lines, the long one keeps its other six.
  const auto selected = SelectSegments(peaks, segments, 10, 3);
  EXPECT_EQ(selected.size(), 10u);
  std::vector<int> lines;
  for (const auto& [p, s] : selected) lines.push_back(peaks[p].line);
  EXPECT_TRUE(std::is_sorted(lines.begin(), lines.end()));
  EXPECT_EQ(std::adjacent_find(lines.begin(), lines.end()), lines.end());
}

// Dark texture breaks the line into pieces; a bright blob beside one (a
// particle lit by the floods) outscores that piece. By score alone the blob
// takes the piece's scan lines; with line continuity the piece keeps them,
// and a segment off the line on scan lines of its own (a shaft in front of a
// hull) is still taken.
TEST(LaserSegments, PiecesContinuingTheLineKeepTheirScanLines) {
  std::vector<Peak> peaks;
  const auto line_at = [](int line) { return 50.0 + 0.2 * line; };
  for (int line = 0; line < 60; ++line) {
    const bool gap = (line >= 10 && line < 13) || (line >= 21 && line < 24);
    // The piece on a dark square between two brighter ones, the last of
    // which outscores the blob (the line's long pieces do).
    const float strength = line < 10 ? 0.2f : (line < 21 ? 0.05f : 0.4f);
    if (!gap && line < 40) peaks.push_back({line, line_at(line), strength, kGreen});
    if (line >= 13 && line < 21) peaks.push_back({line, 110.0, 0.6f, kGreen});   // the blob
    if (line >= 45) peaks.push_back({line, 200.0 + 0.5 * line, 0.15f, kGreen});  // the shaft
  }
  std::sort(peaks.begin(), peaks.end(),
            [](const Peak& a, const Peak& b) { return a.line < b.line; });
  const auto segments = GroupPeaks(peaks, 2, 2);
  ASSERT_EQ(segments.size(), 5u);  // three pieces of the line, the blob, the shaft
  const auto positions_on = [&](const std::vector<std::pair<int, int>>& selected, int from,
                                int to) {
    std::vector<double> positions;
    for (const auto& [p, s] : selected) {
      if (peaks[p].line >= from && peaks[p].line < to) positions.push_back(peaks[p].position);
    }
    return positions;
  };
  const auto by_score = SelectSegments(peaks, segments, 60, 6, 0.0, 0.0);
  for (double position : positions_on(by_score, 13, 21)) EXPECT_EQ(position, 110.0);
  const auto continuous = SelectSegments(peaks, segments, 60, 6, 0.0, 4.0);
  const auto piece = positions_on(continuous, 13, 21);
  ASSERT_EQ(piece.size(), 8u);
  for (size_t i = 0; i < piece.size(); ++i) EXPECT_DOUBLE_EQ(piece[i], line_at(13 + int(i)));
  EXPECT_EQ(positions_on(continuous, 0, 40).size(), 34u);   // the whole line
  EXPECT_EQ(positions_on(continuous, 45, 60).size(), 15u);  // and the shaft
  EXPECT_EQ(positions_on(by_score, 45, 60).size(), 15u);
}

// Marine snow near the lights (sim/marine_snow.cc): a particle lit by the
// red LEDs is bright enough to clip red and to show in green through the
// filters' crosstalk, but has no blue, while the 532 nm line lights blue in
// a fixed share. Where the line is missing (a dark square), such a spot
// beside it would take its scan lines; the cross-channel test cannot judge
// it (red is clipped). One lit by the laser itself has the line's colours
// and stays.
TEST(LaserDetector, SpotsWithoutTheLasersColourSignatureAreDropped) {
  for (const ColourLayout layout : {ColourLayout::kBayerRggb, ColourLayout::kBgr}) {
    SCOPED_TRACE(layout == ColourLayout::kBgr ? "BGR" : "RGGB");
    SyntheticLineOptions o;
    o.layout = layout;
    SyntheticLine line = RenderSyntheticLine(o);
    SyntheticLineOptions dark = o;
    dark.amplitude = 0.0;
    const cv::Mat unlit = RenderSyntheticLine(dark).image;
    unlit.rowRange(100, 125).copyTo(line.image.rowRange(100, 125));  // the line is missing there
    const auto paint_spot = [&](cv::Mat* image, double u, double v, const cv::Vec3d& rgb) {
      for (int y = int(v) - 6; y <= int(v) + 6; ++y) {
        for (int x = int(u) - 6; x <= int(u) + 6; ++x) {
          const double r2 = (x - u) * (x - u) + (y - v) * (y - v);
          const double add = 255.0 * std::exp(-0.5 * r2 / (2.0 * 2.0));
          if (layout == ColourLayout::kBgr) {
            cv::Vec3b& pixel = image->at<cv::Vec3b>(y, x);
            for (int c = 0; c < 3; ++c)
              pixel[2 - c] = cv::saturate_cast<uint8_t>(pixel[2 - c] + add * rgb[c]);
          } else {
            uint8_t& pixel = image->at<uint8_t>(y, x);
            pixel = cv::saturate_cast<uint8_t>(pixel + add * rgb[BayerColourAt(layout, y, x)]);
          }
        }
      }
    };
    const double spot_u = 250.0, spot_v = 112.0;
    const auto points_near_spot = [&](const Detection& detection) {
      return std::count_if(detection.points.begin(), detection.points.end(),
                           [&](const LaserPoint& p) { return std::abs(p.u - spot_u) < 10.0; });
    };
    // Lit by the red LED: red clipped many times over, a few per cent of it
    // in green, no blue.
    cv::Mat flood_lit = line.image.clone();
    paint_spot(&flood_lit, spot_u, spot_v, {40.0, 2.5, 0.0});
    DetectorOptions keep;
    keep.min_signature_share = 0.0;
    const Detection kept = DetectLaserLine(flood_lit, layout, keep);
    EXPECT_GE(points_near_spot(kept), 6);  // without the test the spot takes its scan lines
    const Detection dropped = DetectLaserLine(flood_lit, layout, DetectorOptions{});
    EXPECT_EQ(points_near_spot(dropped), 0);
    EXPECT_GE(dropped.stats.off_colour_segments, 1);
    EXPECT_NEAR(dropped.stats.colour_signature, 0.15, 0.05);  // the line's blue per green
    const Score score = Evaluate(dropped, line);
    EXPECT_LT(score.outliers, 0.005);
    EXPECT_GT(score.completeness, 0.95 * (240 - 25) / 240);
    // Lit by the laser (a particle in the sheet): the line's colours, kept.
    cv::Mat laser_lit = line.image.clone();
    paint_spot(&laser_lit, spot_u, spot_v, o.laser_colour);
    const Detection in_sheet = DetectLaserLine(laser_lit, layout, DetectorOptions{});
    EXPECT_GE(points_near_spot(in_sheet), 6);
    EXPECT_EQ(in_sheet.stats.off_colour_segments, 0);
  }
}

TEST(LaserDetector, RejectsBadImages) {
  EXPECT_THROW(DetectLaserLine(cv::Mat(), ColourLayout::kMono, DetectorOptions{}), Error);
  EXPECT_THROW(DetectLaserLine(cv::Mat(10, 10, CV_32F), ColourLayout::kMono, DetectorOptions{}),
               Error);
  EXPECT_THROW(DetectLaserLine(cv::Mat(10, 10, CV_8UC3), ColourLayout::kMono, DetectorOptions{}),
               Error);
}

}  // namespace
}  // namespace uwscan::laser
