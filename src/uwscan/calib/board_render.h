// Synthetic checkerboard images with known corner positions, for detector
// tests and the detection benchmark: a board texture warped by the
// homography of a distortion-free pinhole view, then blur, turbidity
// (contrast loss towards a veiling-light level) and sensor noise.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "uwscan/calib/board.h"
#include "uwscan/geometry/rigid3d.h"
#include "uwscan/sensor/camera.h"

namespace uwscan {

struct BoardRenderOptions {
  int width = 1280;
  int height = 960;
  double focal_px = 1000.0;  // pinhole, principal point at the centre
  double blur_sigma_px = 0.0;
  double noise_sigma = 0.0;  // grey levels
  double contrast = 1.0;     // 1 clear water; < 1 turbid: I = c I + (1 - c) veil
  double veil = 128.0;       // veiling light level
  double black = 30.0, white = 220.0;
  unsigned seed = 1;
  int supersample = 4;  // rendered at this factor and box-filtered down
};

// RenderBoard's camera as a rig camera: distortion-free pinhole, principal
// point at the image centre.
Camera RenderCamera(const BoardRenderOptions& options);

// Renders the board at camera_from_board; `corners` gets the true corner
// pixels in board order (OpenCV pixel-centre convention).
cv::Mat RenderBoard(const BoardSpec& board, const Rigid3d& camera_from_board,
                    const BoardRenderOptions& options, std::vector<Eigen::Vector2d>* corners);

// The same board seen through any rig camera (pinhole or flat port, with
// distortion): every pixel's ray (Camera::BackProject) meets the board plane,
// rendered at 2x and box-filtered; width, height and focal of `options` are
// ignored. Corners are the exact projections.
cv::Mat RenderBoardThroughCamera(const Camera& camera, const BoardSpec& board,
                                 const Rigid3d& camera_from_board,
                                 const BoardRenderOptions& options,
                                 std::vector<Eigen::Vector2d>* corners);

}  // namespace uwscan
