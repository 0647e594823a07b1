#include "uwscan/calib/laser_points.h"

#include <algorithm>
#include <opencv2/imgproc.hpp>

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

std::vector<Eigen::Vector2d> ExtractLaserPixels(const cv::Mat& image, const BoardSpec& board,
                                                const std::vector<Eigen::Vector2d>& corners,
                                                const LaserPointOptions& options) {
  cv::Mat signal;
  if (image.channels() == 3) {
    std::vector<cv::Mat> bgr;
    cv::Mat image_f;
    image.convertTo(image_f, CV_32F);
    cv::split(image_f, bgr);
    signal = bgr[1] - 0.5 * (bgr[0] + bgr[2]);
  } else {
    image.convertTo(signal, CV_32F);
  }
  // Board outline: the outer inner-corners.
  const int c = board.cols - 1, r = board.rows - 1;
  std::vector<cv::Point> outline;
  for (int index : {0, c, r * board.cols + c, r * board.cols}) {
    outline.emplace_back(static_cast<int>(corners[index].x()),
                         static_cast<int>(corners[index].y()));
  }
  cv::Mat mask = cv::Mat::zeros(signal.size(), CV_8U);
  cv::fillConvexPoly(mask, outline, cv::Scalar(255));
  const auto by_rows = ScanPeaks(signal, mask, options, false);
  const auto by_columns = ScanPeaks(signal.t(), mask.t(), options, true);
  return by_rows.size() >= by_columns.size() ? by_rows : by_columns;
}

}  // namespace uwscan
