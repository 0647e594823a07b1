#include "uwscan/calib/board_render.h"

#include <opencv2/imgproc.hpp>
#include <random>

namespace uwscan {
namespace {

constexpr int kTexturePx = 64;  // texture pixels per square

// Board texture: (cols + 1) x (rows + 1) squares and a white margin of one
// square; texture_from_board maps board metres to texture pixel centres.
cv::Mat BoardTexture(const BoardSpec& board, const BoardRenderOptions& options,
                     Eigen::Matrix3d* texture_from_board) {
  const int px = kTexturePx;
  const int squares_x = board.cols + 1, squares_y = board.rows + 1;
  cv::Mat texture((squares_y + 2) * px, (squares_x + 2) * px, CV_8U, cv::Scalar(options.white));
  for (int y = 0; y < squares_y; ++y) {
    for (int x = 0; x < squares_x; ++x) {
      if ((x + y) % 2 == 0) {
        texture(cv::Rect((x + 1) * px, (y + 1) * px, px, px)).setTo(cv::Scalar(options.black));
      }
    }
  }
  // Inner corner (0, 0) lies on the boundary between texture pixels 2 px - 1 and 2 px.
  const double scale = px / board.square_m;
  const double offset = 2.0 * px - 0.5;
  *texture_from_board << scale, 0, offset, 0, scale, offset, 0, 0, 1;
  return texture;
}

// Blur, turbidity and noise on an 8-bit image.
cv::Mat Degrade(const cv::Mat& image, const BoardRenderOptions& options) {
  cv::Mat value, out;
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
  value.convertTo(out, CV_8U);  // saturates
  return out;
}

}  // namespace

cv::Mat RenderBoardThroughCamera(const Camera& camera, const BoardSpec& board,
                                 const Rigid3d& camera_from_board,
                                 const BoardRenderOptions& options,
                                 std::vector<Eigen::Vector2d>* corners) {
  Eigen::Matrix3d texture_from_board;
  const cv::Mat texture = BoardTexture(board, options, &texture_from_board);
  const Rigid3d board_from_camera = camera_from_board.Inverse();
  const Eigen::Vector3d normal = camera_from_board.rotation * Eigen::Vector3d::UnitZ();
  const double plane = normal.dot(camera_from_board.translation);
  // Ray tracing on a coarse grid of the 2x image, interpolated in between:
  // the map is smooth, and tracing every pixel would take seconds.
  const int s = std::max(1, options.supersample), step = 4;
  const int width = camera.width * s, height = camera.height * s;
  const int grid_w = width / step + 2, grid_h = height / step + 2;
  cv::Mat grid_x(grid_h, grid_w, CV_32F), grid_y(grid_h, grid_w, CV_32F);
  for (int gy = 0; gy < grid_h; ++gy) {
    for (int gx = 0; gx < grid_w; ++gx) {
      // High-res pixel centre -> camera pixel.
      const Eigen::Vector2d pixel((gx * step - 0.5 * (s - 1)) / s, (gy * step - 0.5 * (s - 1)) / s);
      float tx = -1e4f, ty = -1e4f;
      if (const auto ray = camera.BackProject(pixel)) {
        const double denominator = normal.dot(ray->direction);
        const double lambda = (plane - normal.dot(ray->origin)) / denominator;
        if (std::abs(denominator) > 1e-9 && lambda > 0.0) {
          const Eigen::Vector3d on_board = board_from_camera * ray->At(lambda);
          const Eigen::Vector3d t =
              texture_from_board * Eigen::Vector3d(on_board.x(), on_board.y(), 1.0);
          tx = static_cast<float>(t.x());
          ty = static_cast<float>(t.y());
        }
      }
      grid_x.at<float>(gy, gx) = tx;
      grid_y.at<float>(gy, gx) = ty;
    }
  }
  // Grid node g sits at high-res pixel g * step: resize maps nodes to pixels
  // with align-corners semantics over the covered span, then crop.
  const int span_w = (grid_w - 1) * step + 1, span_h = (grid_h - 1) * step + 1;
  cv::Mat map_x, map_y;
  cv::Mat map_x_full(span_h, span_w, CV_32F), map_y_full(span_h, span_w, CV_32F);
  for (int y = 0; y < span_h; ++y) {
    const int gy = std::min(y / step, grid_h - 2);
    const float fy = static_cast<float>(y - gy * step) / step;
    for (int x = 0; x < span_w; ++x) {
      const int gx = std::min(x / step, grid_w - 2);
      const float fx = static_cast<float>(x - gx * step) / step;
      auto lerp = [&](const cv::Mat& g) {
        return (1 - fy) * ((1 - fx) * g.at<float>(gy, gx) + fx * g.at<float>(gy, gx + 1)) +
               fy * ((1 - fx) * g.at<float>(gy + 1, gx) + fx * g.at<float>(gy + 1, gx + 1));
      };
      map_x_full.at<float>(y, x) = lerp(grid_x);
      map_y_full.at<float>(y, x) = lerp(grid_y);
    }
  }
  map_x = map_x_full(cv::Rect(0, 0, width, height));
  map_y = map_y_full(cv::Rect(0, 0, width, height));
  cv::Mat high, image;
  cv::remap(texture, high, map_x, map_y, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(90));
  cv::resize(high, image, cv::Size(camera.width, camera.height), 0, 0, cv::INTER_AREA);
  corners->clear();
  for (const Eigen::Vector3d& p : board.Corners()) {
    const auto pixel = camera.Project(camera_from_board * p);
    corners->push_back(pixel ? *pixel : Eigen::Vector2d(-1, -1));
  }
  return Degrade(image, options);
}

Camera RenderCamera(const BoardRenderOptions& options) {
  Camera camera;
  camera.model = CameraModelId::kPinhole;
  camera.width = options.width;
  camera.height = options.height;
  camera.intrinsics = {options.focal_px, options.focal_px, (options.width - 1) / 2.0,
                       (options.height - 1) / 2.0};
  return camera;
}

cv::Mat RenderBoard(const BoardSpec& board, const Rigid3d& camera_from_board,
                    const BoardRenderOptions& options, std::vector<Eigen::Vector2d>* corners) {
  Eigen::Matrix3d texture_from_board;
  const cv::Mat texture = BoardTexture(board, options, &texture_from_board);
  const Eigen::Matrix3d r = camera_from_board.RotationMatrix();
  Eigen::Matrix3d k;
  k << options.focal_px, 0, (options.width - 1) / 2.0, 0, options.focal_px,
      (options.height - 1) / 2.0, 0, 0, 1;
  // Render at 4x and box-filter down: each pixel integrates its area, as a
  // sensor does (bilinear sampling alone biases corners by ~0.1 px).
  const int s = std::max(1, options.supersample);
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
  return Degrade(image, options);
}

}  // namespace uwscan
