#include "uwscan/calib/board_render.h"

#include <opencv2/imgproc.hpp>
#include <random>

namespace uwscan {

cv::Mat RenderBoard(const BoardSpec& board, const Rigid3d& camera_from_board,
                    const BoardRenderOptions& options, std::vector<Eigen::Vector2d>* corners) {
  // Texture: (cols + 1) x (rows + 1) squares plus a white margin of one square.
  const int px = 64;  // texture pixels per square
  const int squares_x = board.cols + 1, squares_y = board.rows + 1;
  cv::Mat texture((squares_y + 2) * px, (squares_x + 2) * px, CV_8U, cv::Scalar(options.white));
  for (int y = 0; y < squares_y; ++y) {
    for (int x = 0; x < squares_x; ++x) {
      if ((x + y) % 2 == 0) {
        texture(cv::Rect((x + 1) * px, (y + 1) * px, px, px)).setTo(cv::Scalar(options.black));
      }
    }
  }
  // Board metres -> texture pixel centres: inner corner (0, 0) lies on the
  // boundary between texture pixels 2 px - 1 and 2 px.
  const double scale = px / board.square_m;
  const double offset = 2.0 * px - 0.5;
  Eigen::Matrix3d texture_from_board;
  texture_from_board << scale, 0, offset, 0, scale, offset, 0, 0, 1;
  const Eigen::Matrix3d r = camera_from_board.RotationMatrix();
  Eigen::Matrix3d k;
  k << options.focal_px, 0, (options.width - 1) / 2.0, 0, options.focal_px,
      (options.height - 1) / 2.0, 0, 0, 1;
  // Render at 4x and box-filter down: each pixel integrates its area, as a
  // sensor does (bilinear sampling alone biases corners by ~0.1 px).
  const int s = 4;
  Eigen::Matrix3d high_from_low;
  high_from_low << s, 0, 0.5 * (s - 1), 0, s, 0.5 * (s - 1), 0, 0, 1;
  Eigen::Matrix3d image_from_board;
  image_from_board << r.col(0), r.col(1), camera_from_board.translation;
  image_from_board = k * image_from_board;
  const Eigen::Matrix3d image_from_texture =
      high_from_low * image_from_board * texture_from_board.inverse();
  cv::Mat h(3, 3, CV_64F);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) h.at<double>(i, j) = image_from_texture(i, j);
  }
  cv::Mat high, image;
  cv::warpPerspective(texture, high, h, cv::Size(options.width * s, options.height * s),
                      cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(90));
  cv::resize(high, image, cv::Size(options.width, options.height), 0, 0, cv::INTER_AREA);
  corners->clear();
  for (const Eigen::Vector3d& p : board.Corners()) {
    const Eigen::Vector3d q = image_from_board * Eigen::Vector3d(p.x(), p.y(), 1.0);
    corners->emplace_back(q.x() / q.z(), q.y() / q.z());
  }
  cv::Mat value;
  image.convertTo(value, CV_32F);
  if (options.blur_sigma_px > 0.0) {
    cv::GaussianBlur(value, value, cv::Size(0, 0), options.blur_sigma_px);
  }
  value = value * options.contrast + (1.0 - options.contrast) * options.veil;
  if (options.noise_sigma > 0.0) {
    cv::Mat noise(value.size(), CV_32F);
    cv::RNG rng(options.seed);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, options.noise_sigma);
    value += noise;
  }
  value.convertTo(image, CV_8U);  // saturates
  return image;
}

}  // namespace uwscan
