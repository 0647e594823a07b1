// Pose of a checkerboard seen by a calibrated camera (pinhole or flat port).
#pragma once

#include <optional>
#include <vector>

#include "uwscan/calib/board.h"
#include "uwscan/geometry/rigid3d.h"
#include "uwscan/sensor/camera.h"

namespace uwscan {

struct BoardPose {
  Rigid3d camera_from_board;
  double rms_px = 0.0;  // re-projection RMS with the camera's exact model
};

// Planar PnP (IPPE) on the undistorted corners, for a flat port on the
// paraxial pinhole the port becomes (normalised coordinates scaled by
// n_air / n_water, cf. FlatPortModel::PinholeStart), then a pose-only Ceres
// refinement with the exact model. nullopt if no pose fits.
std::optional<BoardPose> EstimateBoardPose(const Camera& camera, const BoardSpec& board,
                                           const std::vector<Eigen::Vector2d>& corners);

}  // namespace uwscan
