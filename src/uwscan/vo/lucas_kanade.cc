#include "uwscan/vo/lucas_kanade.h"

#include <immintrin.h>

#include <algorithm>
#include <cmath>
#include <opencv2/core/utility.hpp>

#include "uwscan/util/error.h"

namespace uwscan::vo {

void LucasKanadeOptions::Check() const {
  UWS_CHECK(window_px >= kMinWindowPx && window_px <= kMaxWindowPx && window_px % 2 == 1,
            "the KLT window must be odd, ", kMinWindowPx, " to ", kMaxWindowPx, " px (is ",
            window_px, ")");
  UWS_CHECK(max_iterations >= 1, "the KLT needs at least one iteration");
  UWS_CHECK(stop_step_px > 0 && std::isfinite(stop_step_px), "the KLT's stop step must be > 0");
  UWS_CHECK(min_eigenvalue >= 0 && std::isfinite(min_eigenvalue),
            "the KLT's minimum eigenvalue must be >= 0");
}

namespace {

// A window's row, padded to whole vectors of 8 floats (the padding's
// gradients are zero, so it adds nothing).
int PaddedWidth(int window_px) { return (window_px + 7) / 8 * 8; }

constexpr int kMaxPadded = (kMaxWindowPx + 7) / 8 * 8;

}  // namespace

int LucasKanadeBorderPx(int window_px) { return PaddedWidth(window_px) + 2; }

namespace {

// One pyramid level: its pixel (0, 0), row step, size, and the region
// around it that may be read (the border the pyramid was built with).
struct Level {
  const uint8_t* origin = nullptr;
  size_t step = 0;
  int cols = 0, rows = 0;
  int min_x = 0, min_y = 0, end_x = 0, end_y = 0;  // readable: [min, end)

  explicit Level(const cv::Mat& image) {
    UWS_CHECK(image.type() == CV_8UC1, "KLT: pyramid levels must be 8-bit grey images");
    cv::Size whole;
    cv::Point offset;
    image.locateROI(whole, offset);
    origin = image.ptr<uint8_t>(0);
    step = image.step[0];
    cols = image.cols;
    rows = image.rows;
    min_x = -offset.x;
    min_y = -offset.y;
    end_x = whole.width - offset.x;
    end_y = whole.height - offset.y;
  }
  // Whether the rectangle of `width` x `height` pixels at (x, y) may be read.
  bool Readable(int x, int y, int width, int height) const {
    return x >= min_x && y >= min_y && x + width <= end_x && y + height <= end_y;
  }
  const uint8_t* Row(int y) const { return origin + static_cast<ptrdiff_t>(y) * step; }
};

// A pyramid's levels; cv::buildOpticalFlowPyramid may have put each
// level's derivatives after it (unused here).
std::vector<Level> Levels(const std::vector<cv::Mat>& pyramid, int window_px) {
  const bool derivatives = pyramid.size() >= 2 && pyramid[1].type() == CV_16SC2;
  const int border = LucasKanadeBorderPx(window_px);
  std::vector<Level> levels;
  for (size_t l = 0; l < pyramid.size(); l += derivatives ? 2 : 1) {
    const Level& level = levels.emplace_back(pyramid[l]);
    UWS_CHECK(level.Readable(-border, -border, pyramid[l].cols + 2 * border,
                             pyramid[l].rows + 2 * border),
              "KLT: pyramid level ", l, " has a border narrower than ", border,
              " px (build it with cv::buildOpticalFlowPyramid and LucasKanadeBorderPx)");
  }
  return levels;
}

// The window of `from` around `p` and its gradients, ready for the
// iterations: values, x and y gradients, row by row in rows of `padded`.
struct Template {
  alignas(32) float value[kMaxWindowPx * kMaxPadded];
  alignas(32) float gx[kMaxWindowPx * kMaxPadded];
  alignas(32) float gy[kMaxWindowPx * kMaxPadded];
  double g11 = 0, g12 = 0, g22 = 0;  // the gradient matrix
};

// The integer part of a coordinate, if it is one an image can have.
bool Floor(float v, int* i, float* fraction) {
  const float f = std::floor(v);
  if (!(std::abs(f) <= 1e6f)) return false;  // also NaN
  *i = static_cast<int>(f);
  *fraction = v - f;
  return true;
}

// Where a window's template starts: its patch (the window with a pixel
// more on every side, for the gradients, and the padding's columns) has
// its top-left pixel (x0, y0) and p's sub-pixel offset (fx, fy).
struct TemplateStart {
  int x0 = 0, y0 = 0;
  float fx = 0, fy = 0;
  float w00 = 0, w01 = 0, w10 = 0, w11 = 0;  // bilinear weights
  // The patch's column c on the row between a and b.
  float Interpolate(const uint8_t* a, const uint8_t* b, int c) const {
    return w00 * static_cast<float>(a[c]) + w01 * static_cast<float>(a[c + 1]) +
           w10 * static_cast<float>(b[c]) + w11 * static_cast<float>(b[c + 1]);
  }
};

constexpr int PatchStep(int padded) { return padded + 8; }  // padded + 2 used

bool Locate(const Level& level, float px, float py, int size, int padded, TemplateStart* start) {
  const int half = size / 2;
  if (!Floor(px - static_cast<float>(half + 1), &start->x0, &start->fx) ||
      !Floor(py - static_cast<float>(half + 1), &start->y0, &start->fy))
    return false;
  if (!level.Readable(start->x0, start->y0, padded + 3, size + 3)) return false;
  const float fx = start->fx, fy = start->fy;
  start->w00 = (1 - fx) * (1 - fy);
  start->w01 = fx * (1 - fy);
  start->w10 = (1 - fx) * fy;
  start->w11 = fx * fy;
  return true;
}

// Scharr's kernel is normalised to grey levels per pixel, and only the
// image's own pixels count: the border's reflected texture is not the
// scene's, and a window that reaches into it would match it. A sample's
// gradient is weighed by how much of its interpolation lies in the image
// (its column's and row's two pixels), and the padding's columns by
// nothing.
float InImage(int i, int n, float f) {
  return (i >= 0 && i < n ? 1.0f - f : 0.0f) + (i + 1 >= 0 && i + 1 < n ? f : 0.0f);
}

void ColumnWeights(const Level& level, const TemplateStart& start, int size, int padded,
                   float* weights) {
  for (int c = 0; c < padded; ++c)
    weights[c] = c < size ? InImage(start.x0 + 1 + c, level.cols, start.fx) / 32.0f : 0.0f;
}

float RowWeight(const Level& level, const TemplateStart& start, int r) {
  return InImage(start.y0 + 1 + r, level.rows, start.fy);
}

// The gradient matrix from its per-column sums, added in order.
void SumColumns(const float* s11, const float* s12, const float* s22, int padded, Template* t) {
  t->g11 = t->g12 = t->g22 = 0;
  for (int c = 0; c < padded; ++c) {
    t->g11 += s11[c];
    t->g12 += s12[c];
    t->g22 += s22[c];
  }
}

// The kernels, for rows padded to P floats (P a multiple of 8, known when
// compiled so that the rows' sums stay in vector registers). Each sum is
// kept per column and the columns added in order at the end, so that
// every vector width gives the same bits.
template <int P>
struct Kernels {
  // Sets t up for the window of `size` around p (level pixels); false if
  // it cannot be read there.
  static bool MakeTemplate(const Level& level, float px, float py, int size, Template* t) {
    TemplateStart start;
    if (!Locate(level, px, py, size, P, &start)) return false;
    alignas(32) float patch[(kMaxWindowPx + 2) * PatchStep(P)];
    for (int r = 0; r < size + 2; ++r) {
      const uint8_t* a = level.Row(start.y0 + r) + start.x0;
      const uint8_t* b = level.Row(start.y0 + r + 1) + start.x0;
      float* out = patch + r * PatchStep(P);
      for (int c = 0; c < P + 2; ++c) out[c] = start.Interpolate(a, b, c);
    }
    float column_weight[P];
    ColumnWeights(level, start, size, P, column_weight);
    float s11[P] = {}, s12[P] = {}, s22[P] = {};
    for (int r = 0; r < size; ++r) {
      const float row_weight = RowWeight(level, start, r);
      const float* up = patch + r * PatchStep(P);
      const float* mid = up + PatchStep(P);
      const float* down = mid + PatchStep(P);
      float* value = t->value + r * P;
      float* gx = t->gx + r * P;
      float* gy = t->gy + r * P;
      for (int c = 0; c < P; ++c) {
        const float inside = column_weight[c] * row_weight;
        const float dx = (3.0f * (up[c + 2] - up[c]) + 10.0f * (mid[c + 2] - mid[c]) +
                          3.0f * (down[c + 2] - down[c])) *
                         inside;
        const float dy = (3.0f * (down[c] - up[c]) + 10.0f * (down[c + 1] - up[c + 1]) +
                          3.0f * (down[c + 2] - up[c + 2])) *
                         inside;
        value[c] = mid[c + 1];
        gx[c] = dx;
        gy[c] = dy;
        s11[c] += dx * dx;
        s12[c] += dx * dy;
        s22[c] += dy * dy;
      }
    }
    SumColumns(s11, s12, s22, P, t);
    return true;
  }

  // The window's mismatch against `to` with its top-left corner at (x, y):
  // b = the sum of (J - I) times the gradient. False if it cannot be read
  // there.
  static bool Mismatch(const Level& level, const Template& t, float x, float y, int size,
                       double* b1, double* b2) {
    int x0, y0;
    float fx, fy;
    if (!Floor(x, &x0, &fx) || !Floor(y, &y0, &fy)) return false;
    if (!level.Readable(x0, y0, P + 1, size + 1)) return false;
    // Interpolated along each row first, then between rows.
    float above[P], below[P], s1[P] = {}, s2[P] = {};
    const uint8_t* a = level.Row(y0) + x0;
    for (int c = 0; c < P; ++c) {
      const float left = a[c];
      above[c] = left + fx * (static_cast<float>(a[c + 1]) - left);
    }
    for (int r = 0; r < size; ++r) {
      const uint8_t* b = level.Row(y0 + r + 1) + x0;
      const float* value = t.value + r * P;
      const float* gx = t.gx + r * P;
      const float* gy = t.gy + r * P;
      for (int c = 0; c < P; ++c) {
        const float left = b[c];
        below[c] = left + fx * (static_cast<float>(b[c + 1]) - left);
        const float e = above[c] + fy * (below[c] - above[c]) - value[c];
        s1[c] += e * gx[c];
        s2[c] += e * gy[c];
        above[c] = below[c];
      }
    }
    double sum1 = 0, sum2 = 0;
    for (int c = 0; c < P; ++c) {
      sum1 += s1[c];
      sum2 += s2[c];
    }
    *b1 = sum1;
    *b2 = sum2;
    return true;
  }
};

// Eight pixels from `row` on, as floats.
__attribute__((target("avx2"), always_inline)) inline __m256 EightAvx2(const uint8_t* row) {
  return _mm256_cvtepi32_ps(
      _mm256_cvtepu8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(row))));
}

// Eight pixels from `row` on, interpolated at fx towards the next ones.
__attribute__((target("avx2"), always_inline)) inline __m256 HorizontalAvx2(const uint8_t* row,
                                                                            __m256 fx) {
  const __m256 left = EightAvx2(row), right = EightAvx2(row + 1);
  return _mm256_add_ps(left, _mm256_mul_ps(fx, _mm256_sub_ps(right, left)));
}

// Kernels<P>::MakeTemplate in AVX2 by hand, the same operations on each
// column in the same order.
template <int P>
__attribute__((target("avx2"))) bool MakeTemplateAvx2(const Level& level, float px, float py,
                                                      int size, Template* t) {
  constexpr int kVectors = P / 8, kStep = PatchStep(P);
  TemplateStart start;
  if (!Locate(level, px, py, size, P, &start)) return false;
  const __m256 w00 = _mm256_set1_ps(start.w00), w01 = _mm256_set1_ps(start.w01),
               w10 = _mm256_set1_ps(start.w10), w11 = _mm256_set1_ps(start.w11);
  alignas(32) float patch[(kMaxWindowPx + 2) * kStep];
  for (int r = 0; r < size + 2; ++r) {
    const uint8_t* a = level.Row(start.y0 + r) + start.x0;
    const uint8_t* b = level.Row(start.y0 + r + 1) + start.x0;
    float* out = patch + r * kStep;
    for (int k = 0; k < kVectors; ++k) {
      const uint8_t* a8 = a + 8 * k;
      const uint8_t* b8 = b + 8 * k;
      const __m256 sum =
          _mm256_add_ps(_mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(w00, EightAvx2(a8)),
                                                    _mm256_mul_ps(w01, EightAvx2(a8 + 1))),
                                      _mm256_mul_ps(w10, EightAvx2(b8))),
                        _mm256_mul_ps(w11, EightAvx2(b8 + 1)));
      _mm256_store_ps(out + 8 * k, sum);
    }
    for (int c = P; c < P + 2; ++c) out[c] = start.Interpolate(a, b, c);
  }
  alignas(32) float column_weight[P];
  ColumnWeights(level, start, size, P, column_weight);
  const __m256 three = _mm256_set1_ps(3.0f), ten = _mm256_set1_ps(10.0f);
  __m256 s11[kVectors], s12[kVectors], s22[kVectors];
  for (int k = 0; k < kVectors; ++k) s11[k] = s12[k] = s22[k] = _mm256_setzero_ps();
  for (int r = 0; r < size; ++r) {
    const __m256 row_weight = _mm256_set1_ps(RowWeight(level, start, r));
    const float* up = patch + r * kStep;
    const float* mid = up + kStep;
    const float* down = mid + kStep;
    for (int k = 0; k < kVectors; ++k) {
      const int c = 8 * k;
      const __m256 u0 = _mm256_load_ps(up + c), u1 = _mm256_loadu_ps(up + c + 1),
                   u2 = _mm256_loadu_ps(up + c + 2);
      const __m256 m0 = _mm256_load_ps(mid + c), m1 = _mm256_loadu_ps(mid + c + 1),
                   m2 = _mm256_loadu_ps(mid + c + 2);
      const __m256 d0 = _mm256_load_ps(down + c), d1 = _mm256_loadu_ps(down + c + 1),
                   d2 = _mm256_loadu_ps(down + c + 2);
      const __m256 inside = _mm256_mul_ps(_mm256_load_ps(column_weight + c), row_weight);
      const __m256 dx =
          _mm256_mul_ps(_mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(three, _mm256_sub_ps(u2, u0)),
                                                    _mm256_mul_ps(ten, _mm256_sub_ps(m2, m0))),
                                      _mm256_mul_ps(three, _mm256_sub_ps(d2, d0))),
                        inside);
      const __m256 dy =
          _mm256_mul_ps(_mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(three, _mm256_sub_ps(d0, u0)),
                                                    _mm256_mul_ps(ten, _mm256_sub_ps(d1, u1))),
                                      _mm256_mul_ps(three, _mm256_sub_ps(d2, u2))),
                        inside);
      _mm256_store_ps(t->value + r * P + c, m1);
      _mm256_store_ps(t->gx + r * P + c, dx);
      _mm256_store_ps(t->gy + r * P + c, dy);
      s11[k] = _mm256_add_ps(s11[k], _mm256_mul_ps(dx, dx));
      s12[k] = _mm256_add_ps(s12[k], _mm256_mul_ps(dx, dy));
      s22[k] = _mm256_add_ps(s22[k], _mm256_mul_ps(dy, dy));
    }
  }
  alignas(32) float c11[P], c12[P], c22[P];
  for (int k = 0; k < kVectors; ++k) {
    _mm256_store_ps(c11 + 8 * k, s11[k]);
    _mm256_store_ps(c12 + 8 * k, s12[k]);
    _mm256_store_ps(c22 + 8 * k, s22[k]);
  }
  SumColumns(c11, c12, c22, P, t);
  return true;
}

// Kernels<P>::Mismatch in AVX2 by hand (the compiler's vectors of it were
// half as wide): the same operations on each column in the same order,
// so the same bits.
template <int P>
__attribute__((target("avx2"))) bool MismatchAvx2(const Level& level, const Template& t, float x,
                                                  float y, int size, double* b1, double* b2) {
  constexpr int kVectors = P / 8;
  int x0, y0;
  float fx, fy;
  if (!Floor(x, &x0, &fx) || !Floor(y, &y0, &fy)) return false;
  if (!level.Readable(x0, y0, P + 1, size + 1)) return false;
  const __m256 vfx = _mm256_set1_ps(fx), vfy = _mm256_set1_ps(fy);
  __m256 above[kVectors], s1[kVectors], s2[kVectors];
  const uint8_t* first = level.Row(y0) + x0;
  for (int k = 0; k < kVectors; ++k) {
    above[k] = HorizontalAvx2(first + 8 * k, vfx);
    s1[k] = _mm256_setzero_ps();
    s2[k] = _mm256_setzero_ps();
  }
  for (int r = 0; r < size; ++r) {
    const uint8_t* row = level.Row(y0 + r + 1) + x0;
    const float* value = t.value + r * P;
    const float* gx = t.gx + r * P;
    const float* gy = t.gy + r * P;
    for (int k = 0; k < kVectors; ++k) {
      const __m256 below = HorizontalAvx2(row + 8 * k, vfx);
      const __m256 e =
          _mm256_sub_ps(_mm256_add_ps(above[k], _mm256_mul_ps(vfy, _mm256_sub_ps(below, above[k]))),
                        _mm256_load_ps(value + 8 * k));
      s1[k] = _mm256_add_ps(s1[k], _mm256_mul_ps(e, _mm256_load_ps(gx + 8 * k)));
      s2[k] = _mm256_add_ps(s2[k], _mm256_mul_ps(e, _mm256_load_ps(gy + 8 * k)));
      above[k] = below;
    }
  }
  alignas(32) float c1[P], c2[P];
  for (int k = 0; k < kVectors; ++k) {
    _mm256_store_ps(c1 + 8 * k, s1[k]);
    _mm256_store_ps(c2 + 8 * k, s2[k]);
  }
  double sum1 = 0, sum2 = 0;
  for (int c = 0; c < P; ++c) {
    sum1 += c1[c];
    sum2 += c2[c];
  }
  *b1 = sum1;
  *b2 = sum2;
  return true;
}

struct KernelPair {
  bool (*make_template)(const Level&, float, float, int, Template*);
  bool (*mismatch)(const Level&, const Template&, float, float, int, double*, double*);
};

// The kernels for rows of P floats: AVX2 where the CPU has it, else the
// portable ones (which the compiler vectorises for any x86-64).
template <int P>
KernelPair KernelsOf(bool avx2) {
  if (avx2) return {MakeTemplateAvx2<P>, MismatchAvx2<P>};
  return {Kernels<P>::MakeTemplate, Kernels<P>::Mismatch};
}

KernelPair KernelsFor(int padded, bool allow_avx2) {
  const bool avx2 = allow_avx2 && __builtin_cpu_supports("avx2");
  switch (padded) {
    case 8:
      return KernelsOf<8>(avx2);
    case 16:
      return KernelsOf<16>(avx2);
    case 24:
      return KernelsOf<24>(avx2);
    case 32:
      return KernelsOf<32>(avx2);
    case 40:
      return KernelsOf<40>(avx2);
    case 48:
      return KernelsOf<48>(avx2);
    case 56:
      return KernelsOf<56>(avx2);
    default:
      return KernelsOf<64>(avx2);
  }
}

// Tracks one point on one level: from `p` in `from` (level pixels), `q`
// in `to` the start and the result. False, q as it was, where the window
// has no texture or cannot be read (off the image).
bool TrackOnLevel(const Level& from, const Level& to, cv::Point2f p, cv::Point2f* q,
                  const LucasKanadeOptions& options, const KernelPair& kernels, Template* t) {
  const int size = options.window_px, half = size / 2;
  if (!kernels.make_template(from, p.x, p.y, size, t)) return false;
  const double g11 = t->g11, g12 = t->g12, g22 = t->g22;
  const double min_eigenvalue =
      (g11 + g22 - std::sqrt((g11 - g22) * (g11 - g22) + 4.0 * g12 * g12)) / (2.0 * size * size);
  const double det = g11 * g22 - g12 * g12;
  if (!(min_eigenvalue >= options.min_eigenvalue) || !(det > 0)) return false;
  const double stop2 = options.stop_step_px * options.stop_step_px;
  float x = q->x - static_cast<float>(half), y = q->y - static_cast<float>(half);
  double previous_dx = 0, previous_dy = 0;
  for (int i = 0; i < options.max_iterations; ++i) {
    double b1, b2;
    if (!kernels.mismatch(to, *t, x, y, size, &b1, &b2)) return false;
    const double dx = (g12 * b2 - g22 * b1) / det, dy = (g12 * b1 - g11 * b2) / det;
    x += static_cast<float>(dx);
    y += static_cast<float>(dy);
    if (dx * dx + dy * dy <= stop2) break;
    // Bouncing between two positions: the middle.
    if (i > 0 && std::abs(dx + previous_dx) < 0.01 && std::abs(dy + previous_dy) < 0.01) {
      x -= static_cast<float>(0.5 * dx);
      y -= static_cast<float>(0.5 * dy);
      break;
    }
    previous_dx = dx;
    previous_dy = dy;
  }
  *q = cv::Point2f(x + static_cast<float>(half), y + static_cast<float>(half));
  return true;
}

}  // namespace

void TrackLucasKanade(const std::vector<cv::Mat>& from, const std::vector<cv::Mat>& to,
                      const std::vector<cv::Point2f>& from_points,
                      std::vector<cv::Point2f>* to_points, std::vector<uint8_t>* status,
                      int max_level, bool from_guess, const LucasKanadeOptions& options) {
  options.Check();
  UWS_CHECK(!from.empty() && !to.empty(), "KLT: empty pyramid");
  UWS_CHECK(!from_guess || to_points->size() == from_points.size(), "KLT: ", to_points->size(),
            " starting positions for ", from_points.size(), " points");
  const std::vector<Level> from_levels = Levels(from, options.window_px),
                           to_levels = Levels(to, options.window_px);
  const int top = std::max(0, std::min({max_level, static_cast<int>(from_levels.size()) - 1,
                                        static_cast<int>(to_levels.size()) - 1}));
  const size_t n = from_points.size();
  if (!from_guess) *to_points = from_points;
  status->assign(n, 1);
  const KernelPair kernels = KernelsFor(PaddedWidth(options.window_px), options.allow_avx2);
  auto track = [&](const cv::Range& range) {
    Template t;
    for (int k = range.start; k < range.end; ++k) {
      const cv::Point2f p0 = from_points[k];
      cv::Point2f& q0 = (*to_points)[k];
      if (!(std::isfinite(p0.x) && std::isfinite(p0.y) && std::isfinite(q0.x) &&
            std::isfinite(q0.y))) {
        (*status)[k] = 0;
        continue;
      }
      cv::Point2f q = q0 * (1.0f / static_cast<float>(1 << top));
      bool tracked = false;
      for (int l = top; l >= 0; --l) {
        // A window without texture or off the image at a coarse level
        // leaves the level's start to the finer ones; at full resolution
        // the point is lost.
        tracked = TrackOnLevel(from_levels[l], to_levels[l],
                               p0 * (1.0f / static_cast<float>(1 << l)), &q, options, kernels, &t);
        if (l > 0) q *= 2.0f;
      }
      if (tracked)
        q0 = q;
      else
        (*status)[k] = 0;
    }
  };
  // Thread-safe: each point writes its own entries only.
  cv::parallel_for_(cv::Range(0, static_cast<int>(n)), track,
                    std::max(1.0, static_cast<double>(n) / 64.0));
}

}  // namespace uwscan::vo
