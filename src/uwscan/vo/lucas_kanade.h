// Pyramidal Lucas-Kanade point tracking (Bouguet's formulation: the
// window's gradient matrix from the first image, Gauss-Newton steps on the
// second, coarse to fine), on the pyramids cv::buildOpticalFlowPyramid
// builds. Our own, for speed: the window's rows are padded to whole SIMD
// vectors, the image is interpolated in floats, and the first image's
// gradients are those of its interpolated window (Scharr's kernel on it),
// which equal the interpolated gradients of the image without computing
// them over the whole image at every call.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

namespace uwscan::vo {

struct LucasKanadeOptions {
  int window_px = 21;  // odd, kMinWindowPx..kMaxWindowPx
  int max_iterations = 30;
  double stop_step_px = 0.01;  // the iterations end at a smaller step
  // A window whose gradient matrix's smaller eigenvalue, per pixel of the
  // window, is below this (grey levels squared per pixel squared) has no
  // texture to track and is lost.
  double min_eigenvalue = 1e-4;
  // The AVX2 kernels where the CPU has them; false: the portable ones.
  // Both give the same bits (lucas_kanade_test compares them).
  bool allow_avx2 = true;
  void Check() const;
};

inline constexpr int kMinWindowPx = 5;
inline constexpr int kMaxWindowPx = 63;

// The border (pixels) a pyramid's levels need around each image for
// windows of `window_px`: pass cv::Size(b, b) as the window size to
// cv::buildOpticalFlowPyramid (it only sets the border there).
int LucasKanadeBorderPx(int window_px);

// Tracks from_points (level-0 pixels of `from`) into `to`, over levels
// max_level..0 (at most the pyramids' own). to_points holds the starting
// positions when `from_guess` is set (otherwise from_points); it ends with
// the tracked ones. status: 1 tracked, 0 lost (no texture, left the image,
// or not finite), as cv::calcOpticalFlowPyrLK's. Each point's result
// depends on it alone. Throws if a pyramid's border is too narrow.
void TrackLucasKanade(const std::vector<cv::Mat>& from, const std::vector<cv::Mat>& to,
                      const std::vector<cv::Point2f>& from_points,
                      std::vector<cv::Point2f>* to_points, std::vector<uint8_t>* status,
                      int max_level, bool from_guess, const LucasKanadeOptions& options);

}  // namespace uwscan::vo
