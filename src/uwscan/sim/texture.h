// Procedural albedo textures, box-filtered over a pixel's footprint so that
// edges are anti-aliased without supersampling:
// - checkerboard: exact box filter of the alternating cells;
// - natural: multi-scale random cells (each octave rotated, values hashed
//   from the seed), giving trackable corners at several scales; octaves
//   finer than the footprint fade to their mean.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace uwscan::sim {

enum class TextureType { kUniform, kNatural, kCheckerboard };

const char* TextureName(TextureType type);
TextureType TextureFromName(const std::string& name, const std::string& context);

struct Texture {
  TextureType type = TextureType::kUniform;
  Eigen::Vector3d albedo = Eigen::Vector3d(0.5, 0.5, 0.5);          // mean (R, G, B), 0..1
  Eigen::Vector3d albedo_dark = Eigen::Vector3d(0.05, 0.05, 0.05);  // checkerboard dark squares
  double contrast = 0.6;  // natural: relative amplitude of the variation
  double scale_m = 0.4;   // natural: largest cell size; checkerboard: square size
  int octaves = 6;        // natural
  uint64_t seed = 1;      // natural
  // Checkerboard: squares in x and y; the board covers
  // [-nx/2, nx/2] x [-ny/2, ny/2] squares around the surface origin and a
  // light margin around it.
  int squares_x = 8;
  int squares_y = 6;
  // A painted stripe over any texture (a marking, a tape): `stripe_width_m`
  // wide (0 = none), centred at s = stripe_s_m, running along t.
  double stripe_width_m = 0.0;
  double stripe_s_m = 0.0;
  double stripe_period_m = 0.0;  // > 0: repeated every period along s
  Eigen::Vector3d stripe_albedo = Eigen::Vector3d(0.9, 0.9, 0.9);

  // Albedo at surface coordinates (s, t) in metres, averaged over a square
  // footprint of side `footprint_m`.
  Eigen::Vector3d Albedo(double s, double t, double footprint_m) const;
  void Check(const std::string& context) const;

  // Caches the per-octave rotations of the natural texture (trigonometry off
  // the per-pixel path). Albedo() works without it, only slower.
  void Prepare();

 private:
  Eigen::Vector3d BaseAlbedo(double s, double t, double footprint_m) const;
  struct Octave {
    double cos_angle, sin_angle, shift_u, shift_v, cell_m, amplitude;
    uint64_t seed;
  };
  Octave MakeOctave(int k) const;
  std::vector<Octave> octaves_;
  uint64_t prepared_seed_ = 0;
  double prepared_scale_m_ = 0.0;
};

}  // namespace uwscan::sim
