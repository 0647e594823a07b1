#include "uwscan/vo/feature_tracker.h"

#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>
#include <unordered_set>

#include "uwscan/util/error.h"

namespace uwscan::vo {

void FeatureTrackerOptions::Check() const {
  UWS_CHECK(grid_cols >= 1 && grid_rows >= 1, "feature grid must be at least 1x1");
  UWS_CHECK(max_per_cell >= 1, "max_per_cell must be >= 1");
  UWS_CHECK(quality_level > 0 && quality_level < 1, "quality_level must be in (0, 1)");
  UWS_CHECK(min_distance_px >= 1, "min_distance_px must be >= 1");
  UWS_CHECK(klt_window_px >= 5 && klt_window_px % 2 == 1, "klt_window_px must be odd and >= 5");
  UWS_CHECK(klt_pyramid_levels >= 0 && klt_pyramid_levels <= 6, "klt_pyramid_levels in 0..6");
  UWS_CHECK(forward_backward_px > 0, "forward_backward_px must be > 0");
  UWS_CHECK(border_px >= 0, "border_px must be >= 0");
}

FeatureTracker::FeatureTracker(const FeatureTrackerOptions& options) : options_(options) {
  options_.Check();
}

void FeatureTracker::Reset() {
  anchor_pyramid_.clear();
  tracks_.clear();
  previous_pyramid_.clear();
  previous_gray_.release();
}

void FeatureTracker::RemoveTracks(const std::vector<uint64_t>& ids) {
  if (ids.empty()) return;
  const std::unordered_set<uint64_t> remove(ids.begin(), ids.end());
  tracks_.erase(std::remove_if(tracks_.begin(), tracks_.end(),
                               [&](const FeatureTrack& t) { return remove.count(t.id) > 0; }),
                tracks_.end());
}

namespace {

bool Masked(const cv::Mat& mask, const cv::Point2f& p) {
  if (mask.empty()) return false;
  const int x = cvRound(p.x), y = cvRound(p.y);
  if (x < 0 || y < 0 || x >= mask.cols || y >= mask.rows) return true;
  return mask.at<uint8_t>(y, x) != 0;
}

}  // namespace

TrackingStats FeatureTracker::Track(const cv::Mat& gray, const cv::Mat& mask) {
  UWS_CHECK(gray.type() == CV_8UC1, "FeatureTracker: expected an 8-bit grey image");
  UWS_CHECK(mask.empty() || (mask.type() == CV_8UC1 && mask.size() == gray.size()),
            "FeatureTracker: mask must be CV_8U and of the image size");
  TrackingStats stats;
  const cv::Size window(options_.klt_window_px, options_.klt_window_px);
  std::vector<cv::Mat> pyramid;
  cv::buildOpticalFlowPyramid(gray, pyramid, window, options_.klt_pyramid_levels);
  if (!previous_gray_.empty() && previous_gray_.size() != gray.size()) Reset();
  if (!previous_pyramid_.empty() && !tracks_.empty()) {
    std::vector<cv::Point2f> previous, current, back;
    for (const auto& t : tracks_) previous.emplace_back(float(t.pixel.x()), float(t.pixel.y()));
    std::vector<uint8_t> status, status_back;
    std::vector<float> error;
    const cv::TermCriteria criteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS,
                                    options_.klt_max_iterations, 0.01);
    cv::calcOpticalFlowPyrLK(previous_pyramid_, pyramid, previous, current, status, error, window,
                             options_.klt_pyramid_levels, criteria);
    back = previous;
    cv::calcOpticalFlowPyrLK(pyramid, previous_pyramid_, current, back, status_back, error, window,
                             options_.klt_pyramid_levels, criteria, cv::OPTFLOW_USE_INITIAL_FLOW);
    if (options_.anchor_refinement && !anchor_pyramid_.empty()) {
      RefineFromAnchor(pyramid, window, criteria, &current);
    }
    std::vector<vo::FeatureTrack> kept;
    kept.reserve(tracks_.size());
    const double b = options_.border_px;
    for (size_t i = 0; i < tracks_.size(); ++i) {
      const cv::Point2f& p = current[i];
      if (!status[i] || !status_back[i] || !std::isfinite(p.x) || !std::isfinite(p.y) ||
          cv::norm(back[i] - previous[i]) > options_.forward_backward_px) {
        ++stats.lost_klt;
        continue;
      }
      if (p.x < b || p.y < b || p.x > gray.cols - 1 - b || p.y > gray.rows - 1 - b) {
        ++stats.lost_border;
        continue;
      }
      if (Masked(mask, p)) {
        ++stats.lost_mask;
        continue;
      }
      vo::FeatureTrack t = tracks_[i];
      t.pixel = Eigen::Vector2d(p.x, p.y);
      ++t.age;
      kept.push_back(t);
    }
    tracks_.swap(kept);
  } else {
    tracks_.clear();
  }
  previous_pyramid_ = std::move(pyramid);
  previous_gray_ = gray;
  stats.tracked = int(tracks_.size());
  return stats;
}

void FeatureTracker::SetAnchor() {
  anchor_pyramid_ = previous_pyramid_;
  for (auto& t : tracks_) {
    t.anchored = true;
    t.anchor_pixel = t.pixel;
  }
}

void FeatureTracker::RefineFromAnchor(const std::vector<cv::Mat>& pyramid, const cv::Size& window,
                                      const cv::TermCriteria& criteria,
                                      std::vector<cv::Point2f>* current) {
  std::vector<cv::Point2f> from, to;
  std::vector<size_t> index;
  for (size_t i = 0; i < tracks_.size(); ++i) {
    if (!tracks_[i].anchored) continue;
    from.emplace_back(float(tracks_[i].anchor_pixel.x()), float(tracks_[i].anchor_pixel.y()));
    to.push_back((*current)[i]);
    index.push_back(i);
  }
  if (from.empty()) return;
  std::vector<uint8_t> status;
  std::vector<float> error;
  // The frame-to-frame position starts within a pixel or so of the answer
  // (a larger correction is refused below): full resolution only, a quarter
  // of the work of the pyramid.
  cv::calcOpticalFlowPyrLK(anchor_pyramid_, pyramid, from, to, status, error, window, 0, criteria,
                           cv::OPTFLOW_USE_INITIAL_FLOW);
  for (size_t k = 0; k < index.size(); ++k) {
    cv::Point2f& p = (*current)[index[k]];
    if (status[k] && std::isfinite(to[k].x) && std::isfinite(to[k].y) &&
        cv::norm(to[k] - p) <= options_.anchor_max_correction_px) {
      p = to[k];
    }
  }
}

int FeatureTracker::Detect(const cv::Mat& mask, TrackingStats* stats) {
  if (previous_gray_.empty()) return 0;
  const cv::Mat& gray = previous_gray_;
  const int cols = options_.grid_cols, rows = options_.grid_rows;
  const double cell_w = double(gray.cols) / cols, cell_h = double(gray.rows) / rows;
  std::vector<int> count(cols * rows, 0);
  auto cell_of = [&](double x, double y) {
    const int cx = std::clamp(int(x / cell_w), 0, cols - 1);
    const int cy = std::clamp(int(y / cell_h), 0, rows - 1);
    return cy * cols + cx;
  };
  for (const auto& t : tracks_) ++count[cell_of(t.pixel.x(), t.pixel.y())];
  bool any = false;
  for (int c : count) any = any || c < options_.max_per_cell;
  if (!any) return 0;

  // Harris response on the whole image, local maxima by 3x3 dilation.
  cv::Mat response, dilated;
  cv::cornerHarris(gray, response, 3, 3, options_.harris_k);
  cv::dilate(response, dilated, cv::Mat());
  // Pixels that may not receive a feature: user mask, border, near existing.
  cv::Mat blocked(gray.size(), CV_8U, cv::Scalar(0));
  if (!mask.empty()) blocked.setTo(255, mask);
  const int r = int(options_.min_distance_px);
  for (const auto& t : tracks_) {
    cv::circle(blocked, cv::Point(cvRound(t.pixel.x()), cvRound(t.pixel.y())), r, 255, -1);
  }
  const int border = int(std::ceil(options_.border_px)) + 1;

  int detected = 0;
  struct Candidate {
    float response;
    int x, y;
  };
  std::vector<Candidate> candidates;
  for (int cy = 0; cy < rows; ++cy) {
    for (int cx = 0; cx < cols; ++cx) {
      const int cell = cy * cols + cx;
      const int quota = options_.max_per_cell - count[cell];
      if (quota <= 0) continue;
      const int x0 = std::max(border, int(cx * cell_w)),
                x1 = std::min(gray.cols - border, int((cx + 1) * cell_w));
      const int y0 = std::max(border, int(cy * cell_h)),
                y1 = std::min(gray.rows - border, int((cy + 1) * cell_h));
      candidates.clear();
      float cell_max = 0.f;
      for (int y = y0; y < y1; ++y) {
        const float* resp = response.ptr<float>(y);
        const float* dil = dilated.ptr<float>(y);
        const uint8_t* blk = blocked.ptr<uint8_t>(y);
        for (int x = x0; x < x1; ++x) {
          if (resp[x] > options_.min_harris_response && resp[x] >= dil[x] && !blk[x]) {
            candidates.push_back({resp[x], x, y});
            cell_max = std::max(cell_max, resp[x]);
          }
        }
      }
      std::sort(candidates.begin(), candidates.end(),
                [](const Candidate& a, const Candidate& b) { return a.response > b.response; });
      int taken = 0;
      for (const Candidate& c : candidates) {
        if (taken >= quota || c.response < options_.quality_level * cell_max) break;
        if (blocked.at<uint8_t>(c.y, c.x)) continue;  // close to one taken just now
        // Sub-pixel corner position would bias little; KLT refines anyway.
        tracks_.push_back({next_id_++, Eigen::Vector2d(c.x, c.y), 0});
        cv::circle(blocked, cv::Point(c.x, c.y), r, 255, -1);
        ++taken;
      }
      detected += taken;
    }
  }
  if (stats != nullptr) stats->detected += detected;
  return detected;
}

}  // namespace uwscan::vo
