#include "uwscan/sim/texture.h"

#include <algorithm>
#include <cmath>

#include "uwscan/util/error.h"

namespace uwscan::sim {
namespace {

uint64_t Mix(uint64_t x) {  // splitmix64 finaliser
  x ^= x >> 30;
  x *= 0xbf58476d1ce4e5b9ULL;
  x ^= x >> 27;
  x *= 0x94d049bb133111ebULL;
  x ^= x >> 31;
  return x;
}

// Hashed cell value in [-1, 1].
double CellValue(uint64_t seed, int64_t i, int64_t j) {
  // One multiply-xorshift round over the combined coordinates: ample for
  // texture, and cheap on the per-pixel path.
  uint64_t h = seed ^ (static_cast<uint64_t>(i) * 0x9E3779B97F4A7C15ULL) ^
               (static_cast<uint64_t>(j) * 0xC2B2AE3D27D4EB4FULL);
  h ^= h >> 32;
  h *= 0xD6E8FEB86659FD93ULL;
  h ^= h >> 32;
  return static_cast<double>(h >> 11) * (2.0 / 9007199254740992.0) - 1.0;
}

// Overlap of the interval [x - w/2, x + w/2] (w < 1, cell units) with cell
// floor(x - w/2) and the next one.
struct Overlap {
  int64_t first;
  double weight_first;  // the next cell gets 1 - weight_first
};

Overlap BoxOverlap(double x, double w) {
  const double lo = x - 0.5 * w;
  const double cell = std::floor(lo);
  Overlap result{static_cast<int64_t>(cell), 1.0};
  if (w <= 0) return result;
  const double boundary = cell + 1.0;
  if (x + 0.5 * w > boundary) result.weight_first = (boundary - lo) / w;
  return result;
}

// Box-filtered piecewise-constant cell function; cell units, w = footprint.
template <typename F>
double FilteredCells(double x, double y, double w, F value) {
  const double width = std::min(w, 0.999);
  const Overlap ox = BoxOverlap(x, width), oy = BoxOverlap(y, width);
  const double wx[2] = {ox.weight_first, 1.0 - ox.weight_first};
  const double wy[2] = {oy.weight_first, 1.0 - oy.weight_first};
  double sum = 0.0;
  for (int a = 0; a < 2; ++a) {
    if (wx[a] <= 0) continue;
    for (int b = 0; b < 2; ++b) {
      if (wy[b] <= 0) continue;
      sum += wx[a] * wy[b] * value(ox.first + a, oy.first + b);
    }
  }
  // Footprints beyond one cell average many cells: fade to the mean (0).
  const double fade = std::clamp(2.0 - w, 0.0, 1.0);
  return sum * fade;
}

constexpr double kOctaveAmplitude[12] = {1.0,      0.7,       0.49,       0.343,
                                         0.2401,   0.16807,   0.117649,   0.0823543,
                                         0.057648, 0.0403536, 0.02824752, 0.019773264};

// 2^k, exact (std::ldexp on the per-pixel path cost a sixth of the texture's time).
constexpr double kPowerOfTwo[12] = {1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024, 2048};

}  // namespace

const char* TextureName(TextureType type) {
  switch (type) {
    case TextureType::kUniform:
      return "uniform";
    case TextureType::kNatural:
      return "natural";
    case TextureType::kCheckerboard:
      return "checkerboard";
  }
  return "uniform";
}

TextureType TextureFromName(const std::string& name, const std::string& context) {
  if (name == "uniform") return TextureType::kUniform;
  if (name == "natural") return TextureType::kNatural;
  if (name == "checkerboard") return TextureType::kCheckerboard;
  UWS_THROW(context, ": texture must be uniform, natural or checkerboard (got '", name, "')");
}

Eigen::Vector3d Texture::Albedo(double s, double t, double footprint_m) const {
  const Eigen::Vector3d base = BaseAlbedo(s, t, footprint_m);
  if (stripe_width_m <= 0.0) return base;
  // Share of the footprint [s - f/2, s + f/2] on the (nearest) stripe.
  const double centre =
      stripe_period_m > 0.0
          ? stripe_s_m + stripe_period_m * std::round((s - stripe_s_m) / stripe_period_m)
          : stripe_s_m;
  const double half = 0.5 * stripe_width_m, f = std::max(footprint_m, 1e-9);
  const double lo = std::max(s - 0.5 * f, centre - half);
  const double hi = std::min(s + 0.5 * f, centre + half);
  const double share = std::clamp((hi - lo) / f, 0.0, 1.0);
  return base + share * (stripe_albedo - base);
}

Eigen::Vector3d Texture::BaseAlbedo(double s, double t, double footprint_m) const {
  switch (type) {
    case TextureType::kUniform:
      return albedo;
    case TextureType::kCheckerboard: {
      // Cell (i, j) with the board's lower-left corner at cell (0, 0); outside
      // the board a light margin (albedo).
      const double x = s / scale_m + 0.5 * squares_x, y = t / scale_m + 0.5 * squares_y;
      const double w = footprint_m / scale_m;
      const int nx = squares_x, ny = squares_y;
      const double dark_share = 0.5 * (1.0 + FilteredCells(x, y, w, [nx, ny](int64_t i, int64_t j) {
                                         if (i < 0 || j < 0 || i >= nx || j >= ny) return -1.0;
                                         return ((i + j) % 2 == 0) ? 1.0 : -1.0;
                                       }));
      return albedo + dark_share * (albedo_dark - albedo);
    }
    case TextureType::kNatural: {
      // Every octave counts in the normalisation (faded ones with mean 0).
      double variation = 0.0, total = 0.0;
      for (int k = 0; k < octaves; ++k) total += kOctaveAmplitude[k];
      const bool cached = octaves_.size() == static_cast<size_t>(octaves) &&
                          prepared_seed_ == seed && prepared_scale_m_ == scale_m;
      for (int k = 0; k < octaves; ++k) {
        const double cells_per_footprint = footprint_m * kPowerOfTwo[k] / scale_m;
        if (cells_per_footprint >= 2.0) break;  // this and all finer octaves faded to their mean
        Octave made;
        if (!cached) made = MakeOctave(k);
        const Octave& o = cached ? octaves_[k] : made;
        const double u = (o.cos_angle * s - o.sin_angle * t) / o.cell_m + o.shift_u;
        const double v = (o.sin_angle * s + o.cos_angle * t) / o.cell_m + o.shift_v;
        const uint64_t octave_seed = o.seed;
        variation += o.amplitude *
                     FilteredCells(u, v, cells_per_footprint, [octave_seed](int64_t i, int64_t j) {
                       return CellValue(octave_seed, i, j);
                     });
      }
      const double factor = std::max(0.0, 1.0 + contrast * 1.7 * variation / total);
      return albedo * factor;
    }
  }
  return albedo;
}

Texture::Octave Texture::MakeOctave(int k) const {
  // Each octave rotated and shifted so that the grids do not align.
  const double angle = 0.7 * (k + 1) + 0.3 * CellValue(seed, k, -1);
  return Octave{std::cos(angle),
                std::sin(angle),
                17.3 * k,
                -9.1 * k,
                scale_m * std::ldexp(1.0, -k),
                kOctaveAmplitude[k],
                Mix(seed + 0x1234567ULL * (k + 1))};
}

void Texture::Prepare() {
  octaves_.clear();
  prepared_seed_ = seed;
  prepared_scale_m_ = scale_m;
  if (type != TextureType::kNatural) return;
  for (int k = 0; k < octaves; ++k) octaves_.push_back(MakeOctave(k));
}

void Texture::Check(const std::string& context) const {
  UWS_CHECK(albedo.allFinite() && albedo.minCoeff() >= 0 && albedo.maxCoeff() <= 1, context,
            ": albedo must be in [0, 1]");
  UWS_CHECK(albedo_dark.allFinite() && albedo_dark.minCoeff() >= 0 && albedo_dark.maxCoeff() <= 1,
            context, ": albedo_dark must be in [0, 1]");
  UWS_CHECK(std::isfinite(scale_m) && scale_m > 0, context, ": scale_m must be positive");
  UWS_CHECK(std::isfinite(contrast) && contrast >= 0 && contrast <= 1, context,
            ": contrast must be in [0, 1]");
  UWS_CHECK(octaves >= 1 && octaves <= 12, context, ": octaves must be 1..12");
  UWS_CHECK(squares_x >= 2 && squares_y >= 2, context, ": checkerboard needs at least 2x2 squares");
  UWS_CHECK(std::isfinite(stripe_width_m) && stripe_width_m >= 0 && std::isfinite(stripe_s_m),
            context, ": stripe width must be >= 0 and its position finite");
  UWS_CHECK(std::isfinite(stripe_period_m) && stripe_period_m >= 0 &&
                (stripe_period_m == 0 || stripe_period_m > 2 * stripe_width_m),
            context, ": stripe period must be 0 or more than twice the stripe width");
  UWS_CHECK(
      stripe_albedo.allFinite() && stripe_albedo.minCoeff() >= 0 && stripe_albedo.maxCoeff() <= 1,
      context, ": stripe albedo must be in [0, 1]");
}

}  // namespace uwscan::sim
