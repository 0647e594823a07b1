// Synthetic VO datasets rendered with vo::testing::PlaneRenderer, in the
// dataset format of architecture.md (rig.yaml, frames.csv, frames/*.png,
// groundtruth.tum), until the image simulator is merged:
//   transect: a survey line over a textured, gently undulating sea floor;
//   hover:    an approach (to initialise) then millimetre micro-motion.
#pragma once

#include <filesystem>
#include <string>

namespace uwscan {

struct SyntheticVoOptions {
  std::string scenario = "transect";  // transect | hover
  int frames = 600;
  int width = 640;         // height = 3/4 width; Flat1 scaled
  double length_m = 20.0;  // transect length
  double altitude_m = 2.0;
  double d_air_m = 0.005;  // Flat1: 5 mm (nearly the optimal air gap)
  double frame_rate_hz = 30.0;
  std::string medium = "clear";  // clear | medium (contrast, backscatter, noise)
  bool laser = true;             // draw a laser line (and put a laser in rig.yaml)
  unsigned seed = 7;
  void Check() const;
};

struct SyntheticVoSummary {
  int frames = 0;
  double path_length_m = 0.0;
  double seconds = 0.0;
};

// Writes the dataset into `dir`, which must not exist or be an empty folder;
// nothing is left under its name if writing fails or is interrupted.
SyntheticVoSummary WriteSyntheticVoDataset(const std::filesystem::path& dir,
                                           const SyntheticVoOptions& options);

}  // namespace uwscan
