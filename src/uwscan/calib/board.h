// Checkerboard target: inner-corner grid (OpenCV's pattern size) and square
// size. Corners lie on the board plane z = 0, row by row, x along columns.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace uwscan {

struct BoardSpec {
  int cols = 9;  // inner corners per row
  int rows = 6;  // inner corners per column
  double square_m = 0.025;

  int NumCorners() const { return cols * rows; }
  // Corner i = r * cols + c at (c * square, r * square, 0) in the board frame.
  std::vector<Eigen::Vector3d> Corners() const;
  // "COLSxROWS:SQUARE_M", e.g. "9x6:0.025"; throws UsageError on bad text.
  static BoardSpec Parse(const std::string& text);
  std::string ToString() const;
  void Check() const;
};

// Corners of one view in board order (BoardSpec::Corners), in pixels.
struct ViewCorners {
  std::string name;
  std::vector<Eigen::Vector2d> corners;
};

// A calibration data set, from images or synthetic.
struct CornerSet {
  BoardSpec board;
  int width = 0;
  int height = 0;
  std::vector<ViewCorners> views;
  void Check(const std::string& context) const;
};

}  // namespace uwscan
