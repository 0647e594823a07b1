#include "uwscan/calib/board.h"

#include <cstdio>
#include <sstream>

#include "uwscan/util/error.h"

namespace uwscan {

std::vector<Eigen::Vector3d> BoardSpec::Corners() const {
  std::vector<Eigen::Vector3d> corners;
  corners.reserve(NumCorners());
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) corners.emplace_back(c * square_m, r * square_m, 0.0);
  }
  return corners;
}

BoardSpec BoardSpec::Parse(const std::string& text) {
  BoardSpec board;
  int consumed = 0;
  if (std::sscanf(text.c_str(), "%dx%d:%lf%n", &board.cols, &board.rows, &board.square_m,
                  &consumed) != 3 ||
      consumed != static_cast<int>(text.size())) {
    throw UsageError("--board '" + text +
                     "': expected COLSxROWS:SQUARE_M (inner corners, metres), e.g. 9x6:0.025");
  }
  try {
    board.Check();
  } catch (const Error& e) {
    throw UsageError("--board '" + text + "': " + e.what());
  }
  return board;
}

std::string BoardSpec::ToString() const {
  std::ostringstream out;
  out << cols << "x" << rows << ":" << square_m;
  return out.str();
}

void BoardSpec::Check() const {
  UWS_CHECK(cols >= 3 && rows >= 3, "a board needs at least 3x3 inner corners, got ", cols, "x",
            rows);
  UWS_CHECK(cols != rows,
            "a square corner grid is ambiguous under rotation; use a board with cols != rows");
  // Up to a metre: a square of 2.5 is centimetres given for metres, which
  // would scale the board's poses and the laser's calibration by 100.
  UWS_CHECK(square_m > 0.0 && square_m <= 1.0,
            "the square size is in metres, in (0, 1] (0.025 for 25 mm squares), got ", square_m);
}

void CornerSet::Check(const std::string& context) const {
  board.Check();
  UWS_CHECK(width > 0 && height > 0, context, ": image size unknown");
  for (const ViewCorners& view : views) {
    UWS_CHECK(static_cast<int>(view.corners.size()) == board.NumCorners(), context, ": view '",
              view.name, "' has ", view.corners.size(), " corners, the board has ",
              board.NumCorners());
  }
}

}  // namespace uwscan
