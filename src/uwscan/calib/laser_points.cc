#include "uwscan/calib/laser_points.h"

#include <algorithm>
#include <opencv2/imgproc.hpp>

#include "uwscan/util/error.h"

namespace uwscan {
namespace {

// Peaks along rows (or columns of the transposed image) inside the mask.
std::vector<Eigen::Vector2d> ScanPeaks(const cv::Mat& signal, const cv::Mat& mask,
                                       const LaserPointOptions& options, bool transposed) {
  std::vector<Eigen::Vector2d> pixels;
  for (int r = 0; r < signal.rows; ++r) {
    const float* row = signal.ptr<float>(r);
    const uchar* inside = mask.ptr<uchar>(r);
    std::vector<float> values;
    int best = -1;
    for (int c = 0; c < signal.cols; ++c) {
      if (!inside[c]) continue;
      values.push_back(row[c]);
      if (best < 0 || row[c] > row[best]) best = c;
    }
    if (best < 0 || values.size() < 10) continue;
    std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
    const float background = values[values.size() / 2];
    if (row[best] - background < options.min_peak) continue;
    double sum = 0.0, weighted = 0.0;
    for (int c = std::max(0, best - options.half_window);
         c <= std::min(signal.cols - 1, best + options.half_window); ++c) {
      const double w = std::max(0.0f, row[c] - background);
      sum += w;
      weighted += w * c;
    }
    if (sum <= 0.0) continue;
    const double peak = weighted / sum;
    pixels.push_back(transposed ? Eigen::Vector2d(r, peak) : Eigen::Vector2d(peak, r));
  }
  return pixels;
}

}  // namespace


std::vector<cv::Point2f> TargetOutline(const Camera& camera, const BoardSpec& board,
                                       const Rigid3d& camera_from_board, double margin_m) {
  const double s = board.square_m;
  const double x0 = -s - margin_m, x1 = board.cols * s + margin_m;
  const double y0 = -s - margin_m, y1 = board.rows * s + margin_m;
  const Eigen::Vector2d corners[4] = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
  constexpr int kSamplesPerEdge = 32;
  std::vector<cv::Point2f> outline;
  for (int edge = 0; edge < 4; ++edge) {
    const Eigen::Vector2d& a = corners[edge];
    const Eigen::Vector2d& b = corners[(edge + 1) % 4];
    for (int i = 0; i < kSamplesPerEdge; ++i) {
      const Eigen::Vector2d p = a + (b - a) * (static_cast<double>(i) / kSamplesPerEdge);
      const auto pixel = camera.Project(camera_from_board * Eigen::Vector3d(p.x(), p.y(), 0.0));
      if (pixel) outline.emplace_back(static_cast<float>(pixel->x()), static_cast<float>(pixel->y()));
    }
  }
  return outline;
}

std::vector<Eigen::Vector2d> DetectLaserOnTarget(const cv::Mat& image,
                                                 const std::vector<cv::Point2f>& outline,
                                                 int laser_channel,
                                                 const LaserPointOptions& options) {
  UWS_CHECK(image.channels() == 1 || image.channels() == 3,
            "laser points: expected a mono or B G R image, got ", image.channels(), " channels");
  UWS_CHECK(laser_channel >= 0 && laser_channel <= 2,
            "laser points: laser channel must be red (0), green (1) or blue (2)");
  if (outline.size() < 3) return {};
  cv::Mat signal;
  const double to_8bit = image.depth() == CV_16U ? 1.0 / 257.0 : 1.0;
  if (image.channels() == 3) {
    std::vector<cv::Mat> bgr;
    cv::split(image, bgr);
    const int own = 2 - laser_channel;  // B G R storage of an R G B channel index
    cv::addWeighted(bgr[(own + 1) % 3], -0.5 * to_8bit, bgr[(own + 2) % 3], -0.5 * to_8bit, 0.0,
                    signal, CV_32F);
    cv::Mat own_f;
    bgr[own].convertTo(own_f, CV_32F, to_8bit);
    signal += own_f;
  } else {
    image.convertTo(signal, CV_32F, to_8bit);
  }
  std::vector<cv::Point> polygon;
  for (const cv::Point2f& p : outline) polygon.emplace_back(cvRound(p.x), cvRound(p.y));
  cv::Mat mask = cv::Mat::zeros(signal.size(), CV_8U);
  cv::fillPoly(mask, std::vector<std::vector<cv::Point>>{polygon}, cv::Scalar(255));
  const auto by_rows = ScanPeaks(signal, mask, options, false);
  const auto by_columns = ScanPeaks(signal.t(), mask.t(), options, true);
  return by_rows.size() >= by_columns.size() ? by_rows : by_columns;
}

}  // namespace uwscan
