// Synthetic checkerboard observations with ground truth: boards at random
// poses in a range band, projected with the exact model of a camera, plus
// Gaussian corner noise. Feeds tests and the detector benchmark until the
// simulator's image scenarios exist.
#pragma once

#include <vector>

#include "uwscan/calib/board.h"
#include "uwscan/geometry/rigid3d.h"
#include "uwscan/sensor/camera.h"

namespace uwscan {

struct SyntheticViewOptions {
  int num_views = 15;
  double min_range_m = 0.3;  // distance of the board centre from the camera
  double max_range_m = 0.7;
  double max_tilt_deg = 35.0;  // board normal against the viewing ray
  double noise_px = 0.0;       // std of Gaussian noise per coordinate
  double margin_px = 10.0;     // every corner this far inside the image
  unsigned seed = 1;
  void Check() const;
};

// Throws uwscan::Error if no valid pose is found after many tries (board
// too large for the range band).
CornerSet SyntheticCornerSet(const Camera& truth, const BoardSpec& board,
                             const SyntheticViewOptions& options,
                             std::vector<Rigid3d>* camera_from_board = nullptr);

// The test camera of the aquarium set-up (thesis §6.1): Pin-Air-like
// intrinsics (1280x960, f 1112.7 px) behind a 6 mm window (n 1.52), fresh
// water 1.333, the window `d_air_m` from the centre and tilted about y.
Camera AquariumTestCamera(double d_air_m, double tilt_deg);

// Exact projections of board corners at a given pose; false if any corner
// does not project inside the image.
bool ProjectBoard(const Camera& camera, const BoardSpec& board, const Rigid3d& camera_from_board,
                  double margin_px, std::vector<Eigen::Vector2d>* corners);

}  // namespace uwscan
