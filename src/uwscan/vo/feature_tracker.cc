#include "uwscan/vo/feature_tracker.h"

#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>
#include <optional>
#include <unordered_set>

#include "uwscan/util/error.h"
#include "uwscan/vo/lucas_kanade.h"

namespace uwscan::vo {

void FeatureTrackerOptions::Check() const {
  UWS_CHECK(grid_cols >= 1 && grid_rows >= 1, "feature grid must be at least 1x1");
  UWS_CHECK(max_per_cell >= 1, "max_per_cell must be >= 1");
  UWS_CHECK(quality_level > 0 && quality_level < 1, "quality_level must be in (0, 1)");
  UWS_CHECK(min_distance_px >= 1, "min_distance_px must be >= 1");
  Klt().Check();
  UWS_CHECK(klt_pyramid_levels >= 0 && klt_pyramid_levels <= 6, "klt_pyramid_levels in 0..6");
  UWS_CHECK(klt_predicted_levels <= 6, "klt_predicted_levels must be <= 6");
  UWS_CHECK(anchor_keep_keyframes >= 0, "anchor_keep_keyframes must be >= 0");
  UWS_CHECK(forward_backward_px > 0, "forward_backward_px must be > 0");
  UWS_CHECK(border_px >= 0, "border_px must be >= 0");
  UWS_CHECK(max_dormant_frames >= 0, "max_dormant_frames must be >= 0");
  UWS_CHECK(reacquire_neighbours >= 1, "reacquire_neighbours must be >= 1");
  UWS_CHECK(reacquire_max_offset_px > 0, "reacquire_max_offset_px must be > 0");
  UWS_CHECK(reacquire_min_correlation >= -1 && reacquire_min_correlation <= 1,
            "reacquire_min_correlation must be in [-1, 1]");
}

LucasKanadeOptions FeatureTrackerOptions::Klt() const {
  LucasKanadeOptions klt;
  klt.window_px = klt_window_px;
  klt.max_iterations = klt_max_iterations;
  return klt;
}

FeatureTracker::FeatureTracker(const FeatureTrackerOptions& options)
    : options_(options), klt_(options.Klt()) {
  options_.Check();
}

void FeatureTracker::Reset() {
  anchor_pyramid_.reset();
  refinement_anchors_.clear();
  anchor_mask_.release();
  tracks_.clear();
  dormant_.clear();
  previous_pyramid_.reset();
  previous_gray_.release();
}

void FeatureTracker::RemoveTracks(const std::vector<uint64_t>& ids) {
  if (ids.empty()) return;
  const std::unordered_set<uint64_t> remove(ids.begin(), ids.end());
  tracks_.erase(std::remove_if(tracks_.begin(), tracks_.end(),
                               [&](const FeatureTrack& t) { return remove.count(t.id) > 0; }),
                tracks_.end());
  dormant_.erase(
      std::remove_if(dormant_.begin(), dormant_.end(),
                     [&](const DormantTrack& d) { return remove.count(d.track.id) > 0; }),
      dormant_.end());
}

void FeatureTracker::MoveTracks(
    const std::function<std::optional<Eigen::Vector2d>(const FeatureTrack&)>& where) {
  for (auto& track : tracks_) {
    if (const auto pixel = where(track)) track.pixel = *pixel;
  }
}

namespace {

bool Masked(const cv::Mat& mask, const cv::Point2f& p) {
  if (mask.empty()) return false;
  const int x = cvRound(p.x), y = cvRound(p.y);
  if (x < 0 || y < 0 || x >= mask.cols || y >= mask.rows) return true;
  return mask.at<uint8_t>(y, x) != 0;
}

// True if the mask is set anywhere within `radius` pixels (a square) of p.
bool MaskedNear(const cv::Mat& mask, const Eigen::Vector2d& p, int radius) {
  if (mask.empty()) return false;
  const int x = int(std::lround(p.x())), y = int(std::lround(p.y()));
  if (x - radius < 0 || y - radius < 0 || x + radius >= mask.cols || y + radius >= mask.rows) {
    return true;
  }
  for (int v = y - radius; v <= y + radius; ++v) {
    const uint8_t* row = mask.ptr<uint8_t>(v);
    for (int u = x - radius; u <= x + radius; ++u) {
      if (row[u]) return true;
    }
  }
  return false;
}

// Normalised cross-correlation of the 11x11 patches around a in A and b in B.
double PatchCorrelation(const cv::Mat& A, const cv::Point2f& a, const cv::Mat& B,
                        const cv::Point2f& b) {
  cv::Mat pa, pb;
  cv::getRectSubPix(A, cv::Size(11, 11), a, pa, CV_32F);
  cv::getRectSubPix(B, cv::Size(11, 11), b, pb, CV_32F);
  cv::Mat result;
  cv::matchTemplate(pa, pb, result, cv::TM_CCOEFF_NORMED);
  return double(result.at<float>(0, 0));
}

// The median displacement (per axis) of the `neighbours` nearest of the
// points that moved from `from` to `to`: the flow is smooth over a few tens
// of pixels. None with fewer than 3 points.
class NeighbourFlow {
 public:
  NeighbourFlow(const std::vector<Eigen::Vector2d>& from, const std::vector<Eigen::Vector2d>& to,
                int neighbours)
      : from_(from),
        to_(to),
        k_(std::min(from.size(), size_t(neighbours))),
        nearest_(from.size()),
        dx_(k_),
        dy_(k_) {}
  std::optional<Eigen::Vector2d> At(const Eigen::Vector2d& p) {
    if (k_ < 3) return std::nullopt;
    for (size_t j = 0; j < from_.size(); ++j) nearest_[j] = {(from_[j] - p).squaredNorm(), j};
    std::partial_sort(nearest_.begin(), nearest_.begin() + std::ptrdiff_t(k_), nearest_.end());
    for (size_t n = 0; n < k_; ++n) {
      const Eigen::Vector2d f = to_[nearest_[n].second] - from_[nearest_[n].second];
      dx_[n] = f.x();
      dy_[n] = f.y();
    }
    std::nth_element(dx_.begin(), dx_.begin() + std::ptrdiff_t(k_ / 2), dx_.end());
    std::nth_element(dy_.begin(), dy_.begin() + std::ptrdiff_t(k_ / 2), dy_.end());
    return Eigen::Vector2d(dx_[k_ / 2], dy_[k_ / 2]);
  }

 private:
  const std::vector<Eigen::Vector2d>& from_;
  const std::vector<Eigen::Vector2d>& to_;
  size_t k_;
  std::vector<std::pair<double, size_t>> nearest_;
  std::vector<double> dx_, dy_;
};

bool Inside(const cv::Point2f& p, const cv::Size& size, double border) {
  return std::isfinite(p.x) && std::isfinite(p.y) && p.x >= border && p.y >= border &&
         p.x <= size.width - 1 - border && p.y <= size.height - 1 - border;
}

}  // namespace

void FeatureTracker::TrackForwardBackward(const std::vector<cv::Mat>& pyramid,
                                          std::vector<cv::Point2f>* current,
                                          std::vector<uint8_t>* consistent,
                                          std::vector<uint8_t>* from_prediction) const {
  const size_t n = tracks_.size();
  std::vector<cv::Point2f> previous, back;
  previous.reserve(n);
  for (const auto& t : tracks_) previous.emplace_back(float(t.pixel.x()), float(t.pixel.y()));
  std::vector<uint8_t> status, status_back;
  // The backward pass starts where a consistent track must end (the
  // previous position), so full resolution suffices: a track that does
  // not come back to within the check from there is rejected either way.
  auto backward = [&](const std::vector<cv::Point2f>& from, const std::vector<cv::Point2f>& start,
                      std::vector<cv::Point2f>* to, std::vector<uint8_t>* ok) {
    *to = start;
    TrackLucasKanade(pyramid, *previous_pyramid_, from, to, ok, 0, true, klt_);
  };
  auto check = [&](size_t i) {
    const cv::Point2f& p = (*current)[i];
    return status[i] && status_back[i] && std::isfinite(p.x) && std::isfinite(p.y) &&
           cv::norm(back[i] - previous[i]) <= options_.forward_backward_px;
  };
  from_prediction->assign(n, 0);
  const int full = options_.klt_pyramid_levels;
  const int predicted_levels = options_.klt_predicted_levels;
  if (predicted_levels < 0 || predicted_levels >= full) {
    TrackLucasKanade(*previous_pyramid_, pyramid, previous, current, &status, full, false, klt_);
    backward(*current, previous, &back, &status_back);
  } else {
    // Each track starts where its last displacement predicts it (a smooth
    // motion, as of a hovering platform at a high frame rate), so the top
    // of the pyramid is not needed; the tracks that fail from there, or end
    // farther from the prediction than the lower levels reach, are tracked
    // again from scratch over the full pyramid.
    std::vector<cv::Point2f> predicted(n);
    for (size_t i = 0; i < n; ++i) {
      const FeatureTrack& t = tracks_[i];
      predicted[i] = cv::Point2f(float(t.pixel.x() + t.flow.x()), float(t.pixel.y() + t.flow.y()));
    }
    *current = predicted;
    TrackLucasKanade(*previous_pyramid_, pyramid, previous, current, &status, predicted_levels,
                     true, klt_);
    backward(*current, previous, &back, &status_back);
    const double reach = double(1 << predicted_levels) * options_.klt_window_px / 4.0;
    std::vector<size_t> retry;
    for (size_t i = 0; i < n; ++i) {
      const bool again = !check(i) || cv::norm((*current)[i] - predicted[i]) > reach;
      (*from_prediction)[i] = !again;
      if (again) retry.push_back(i);
    }
    if (!retry.empty()) {
      std::vector<cv::Point2f> from, to, to_back;
      std::vector<uint8_t> ok, ok_back;
      for (size_t i : retry) from.push_back(previous[i]);
      TrackLucasKanade(*previous_pyramid_, pyramid, from, &to, &ok, full, false, klt_);
      backward(to, from, &to_back, &ok_back);
      for (size_t k = 0; k < retry.size(); ++k) {
        const size_t i = retry[k];
        (*current)[i] = to[k];
        back[i] = to_back[k];
        status[i] = ok[k];
        status_back[i] = ok_back[k];
      }
    }
  }
  consistent->resize(n);
  for (size_t i = 0; i < n; ++i) (*consistent)[i] = check(i);
}

TrackingStats FeatureTracker::Track(const cv::Mat& gray, const cv::Mat& mask) {
  UWS_CHECK(gray.type() == CV_8UC1, "FeatureTracker: expected an 8-bit grey image");
  UWS_CHECK(mask.empty() || (mask.type() == CV_8UC1 && mask.size() == gray.size()),
            "FeatureTracker: mask must be CV_8U and of the image size");
  TrackingStats stats;
  // The levels with the border our KLT reads, without OpenCV's
  // derivatives (it interpolates its windows' own).
  const int border = LucasKanadeBorderPx(options_.klt_window_px);
  auto built = std::make_shared<std::vector<cv::Mat>>();
  cv::buildOpticalFlowPyramid(gray, *built, cv::Size(border, border), options_.klt_pyramid_levels,
                              /*withDerivatives=*/false);
  const Pyramid pyramid = built;
  if (!previous_gray_.empty() && previous_gray_.size() != gray.size()) Reset();
  if (previous_pyramid_ && !tracks_.empty()) {
    std::vector<cv::Point2f> current;
    std::vector<uint8_t> consistent, from_prediction;
    TrackForwardBackward(*pyramid, &current, &consistent, &from_prediction);
    if (options_.anchor_refinement && anchor_pyramid_) RefineFromAnchor(*pyramid, &current);
    std::vector<vo::FeatureTrack> kept;
    std::vector<Eigen::Vector2d> flow_from, flow_to;
    kept.reserve(tracks_.size());
    const bool keep_dormant = options_.max_dormant_frames > 0;
    for (size_t i = 0; i < tracks_.size(); ++i) {
      // (The anchor refinement keeps a finite position finite and moves
      // no other: the check made before it still holds.)
      const cv::Point2f& p = current[i];
      if (!consistent[i]) {
        ++stats.lost_klt;
        // Lost as the line entered its window: may come back once it has passed.
        if (keep_dormant && MaskedNear(mask, tracks_[i].pixel, options_.klt_window_px / 2 + 2)) {
          KeepDormant(tracks_[i]);
        }
        continue;
      }
      if (!Inside(p, gray.size(), options_.border_px)) {
        ++stats.lost_border;
        continue;
      }
      if (Masked(mask, p)) {
        ++stats.lost_mask;
        if (keep_dormant) KeepDormant(tracks_[i]);
        continue;
      }
      vo::FeatureTrack t = tracks_[i];
      flow_from.push_back(t.pixel);
      const Eigen::Vector2d moved(p.x, p.y);
      t.flow = moved - t.pixel;
      t.pixel = moved;
      flow_to.push_back(t.pixel);
      ++t.age;
      stats.predicted += from_prediction[i];
      kept.push_back(t);
    }
    tracks_.swap(kept);
    if (!dormant_.empty()) Reacquire(*pyramid, mask, flow_from, flow_to, &stats);
  } else {
    tracks_.clear();
    dormant_.clear();
  }
  previous_pyramid_ = pyramid;
  previous_gray_ = gray;
  stats.tracked = int(tracks_.size());
  return stats;
}

void FeatureTracker::KeepDormant(const FeatureTrack& track) {
  // Only a track whose anchor patch is clear of the line: a line in the
  // anchor patch would be matched to the line's new place, not the corner's.
  if (!track.anchored || MaskedNear(anchor_mask_, track.anchor_pixel, options_.klt_window_px / 2)) {
    return;
  }
  dormant_.push_back({track, anchor_pyramid_});
}

void FeatureTracker::Reacquire(const std::vector<cv::Mat>& pyramid, const cv::Mat& mask,
                               const std::vector<Eigen::Vector2d>& flow_from,
                               const std::vector<Eigen::Vector2d>& flow_to, TrackingStats* stats) {
  // Carry each dormant position with the median flow of its nearest live
  // neighbours (the flow is smooth over a few tens of pixels), age them.
  NeighbourFlow flow(flow_from, flow_to, options_.reacquire_neighbours);
  for (DormantTrack& d : dormant_) {
    ++d.frames;
    const auto f = flow.At(d.track.pixel);
    if (!f) continue;  // no flow to carry it: it stays where it was
    d.track.flow = *f;
    d.track.pixel += d.track.flow;
  }
  const cv::Size size = pyramid.front().size();
  const double b = options_.border_px;
  dormant_.erase(
      std::remove_if(dormant_.begin(), dormant_.end(),
                     [&](const DormantTrack& d) {
                       const cv::Point2f p(float(d.track.pixel.x()), float(d.track.pixel.y()));
                       return d.frames > options_.max_dormant_frames || !Inside(p, size, b);
                     }),
      dormant_.end());

  // Look again for those clear of the mask, from their anchor images.
  // Only once the KLT window is clear of the mask: a bright line in the
  // window would pull the match towards itself.
  const int clearance = options_.klt_window_px / 2;
  std::vector<size_t> candidates;
  for (size_t i = 0; i < dormant_.size(); ++i) {
    if (!MaskedNear(mask, dormant_[i].track.pixel, clearance)) candidates.push_back(i);
  }
  // dormant_ is in the order the tracks went dormant, each with the anchor
  // of its time, so those of one anchor image stand together: the runs
  // below are its groups, oldest first. (Not sorted by address: heap
  // addresses differ from run to run when another thread allocates, and
  // the order decides which of two tracks revived onto one corner is kept.)
  std::vector<bool> revived(dormant_.size(), false);
  for (size_t begin = 0; begin < candidates.size();) {
    const Pyramid& anchor = dormant_[candidates[begin]].anchor;
    size_t end = begin;
    std::vector<cv::Point2f> from, to;
    while (end < candidates.size() && dormant_[candidates[end]].anchor == anchor) {
      const FeatureTrack& t = dormant_[candidates[end]].track;
      from.emplace_back(float(t.anchor_pixel.x()), float(t.anchor_pixel.y()));
      to.emplace_back(float(t.pixel.x()), float(t.pixel.y()));
      ++end;
    }
    const std::vector<cv::Point2f> predicted = to;
    std::vector<cv::Point2f> back = from;
    std::vector<uint8_t> status, status_back;
    TrackLucasKanade(*anchor, pyramid, from, &to, &status, options_.klt_pyramid_levels, true, klt_);
    TrackLucasKanade(pyramid, *anchor, to, &back, &status_back, options_.klt_pyramid_levels, true,
                     klt_);
    for (size_t n = 0; n < from.size(); ++n) {
      const cv::Point2f& p = to[n];
      if (!status[n] || !status_back[n] || !Inside(p, size, b) ||
          MaskedNear(mask, Eigen::Vector2d(p.x, p.y), clearance) ||
          cv::norm(back[n] - from[n]) > options_.forward_backward_px ||
          cv::norm(p - predicted[n]) > options_.reacquire_max_offset_px) {
        continue;
      }
      // Appearance as in the anchor (KLT converges somewhere on a weak
      // patch; the correlation says whether it is the same corner).
      if (PatchCorrelation((*anchor)[0], from[n], pyramid[0], p) <
          options_.reacquire_min_correlation) {
        continue;
      }
      DormantTrack& d = dormant_[candidates[begin + n]];
      FeatureTrack t = d.track;
      t.pixel = Eigen::Vector2d(p.x, p.y);
      ++t.age;
      t.anchored =
          anchor == anchor_pyramid_;  // refined from the anchor only if it is the current one
      // The corner may have been detected again meanwhile as a new track
      // (or another dormant track revived onto it): the live one stays.
      const double duplicate = 0.5 * options_.min_distance_px;
      const bool near = std::any_of(tracks_.begin(), tracks_.end(), [&](const FeatureTrack& live) {
        return (live.pixel - t.pixel).norm() <= duplicate;
      });
      revived[candidates[begin + n]] = true;  // found: no longer dormant either way
      if (near) continue;
      tracks_.push_back(t);
      ++stats->reacquired;
    }
    begin = end;
  }
  size_t w = 0;
  for (size_t i = 0; i < dormant_.size(); ++i) {
    if (!revived[i]) dormant_[w++] = std::move(dormant_[i]);
  }
  dormant_.resize(w);
}

void FeatureTracker::SetAnchor(const cv::Mat& mask, bool view_moved) {
  anchor_pyramid_ = previous_pyramid_;
  anchor_mask_ = mask.clone();
  std::unordered_map<uint64_t, RefinementAnchor> refinement;
  for (auto& t : tracks_) {
    t.anchored = true;
    t.anchor_pixel = t.pixel;
    const auto it = refinement_anchors_.find(t.id);
    if (!view_moved && it != refinement_anchors_.end() &&
        it->second.keyframes < options_.anchor_keep_keyframes) {
      RefinementAnchor kept = it->second;
      ++kept.keyframes;
      refinement.emplace(t.id, std::move(kept));
    } else {
      refinement.emplace(t.id, RefinementAnchor{anchor_pyramid_, t.pixel, 0});
    }
  }
  refinement_anchors_.swap(refinement);
}

void FeatureTracker::RefineFromAnchor(const std::vector<cv::Mat>& pyramid,
                                      std::vector<cv::Point2f>* current) {
  // The tracks by the anchor image they are refined from: their own kept
  // one (anchor_keep_keyframes), else the last keyframe's.
  std::vector<std::pair<const std::vector<cv::Mat>*, std::vector<size_t>>> groups;
  std::unordered_map<const std::vector<cv::Mat>*, size_t> group_of;
  std::vector<cv::Point2f> from(tracks_.size());
  for (size_t i = 0; i < tracks_.size(); ++i) {
    const FeatureTrack& t = tracks_[i];
    if (!t.anchored) continue;
    const std::vector<cv::Mat>* image = anchor_pyramid_.get();
    Eigen::Vector2d pixel = t.anchor_pixel;
    const auto kept = refinement_anchors_.find(t.id);
    if (kept != refinement_anchors_.end()) {
      image = kept->second.pyramid.get();
      pixel = kept->second.pixel;
    }
    from[i] = cv::Point2f(float(pixel.x()), float(pixel.y()));
    const auto [it, added] = group_of.emplace(image, groups.size());
    if (added) groups.push_back({image, {}});
    groups[it->second].second.push_back(i);
  }
  for (const auto& [image, members] : groups) {
    std::vector<cv::Point2f> start, to;
    for (size_t i : members) start.push_back(from[i]), to.push_back((*current)[i]);
    std::vector<uint8_t> status;
    // The frame-to-frame position starts within a pixel or so of the
    // answer (a larger correction is refused below): full resolution only,
    // a quarter of the work of the pyramid.
    TrackLucasKanade(*image, pyramid, start, &to, &status, 0, true, klt_);
    for (size_t k = 0; k < members.size(); ++k) {
      cv::Point2f& p = (*current)[members[k]];
      if (status[k] && std::isfinite(to[k].x) && std::isfinite(to[k].y) &&
          cv::norm(to[k] - p) <= options_.anchor_max_correction_px) {
        p = to[k];
      }
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
      if (x1 <= x0 || y1 <= y0) continue;
      // Harris response (local maxima by 3x3 dilation) only in the cells
      // that need features, on the cell and a margin: Sobel reads the image
      // around the region, so the values inside are those of the whole
      // image's response, at a fraction of the cost.
      const int margin = 4;
      const cv::Rect region =
          cv::Rect(x0 - margin, y0 - margin, x1 - x0 + 2 * margin, y1 - y0 + 2 * margin) &
          cv::Rect(0, 0, gray.cols, gray.rows);
      cv::Mat response, dilated;
      cv::cornerHarris(gray(region), response, 3, 3, options_.harris_k);
      cv::dilate(response, dilated, cv::Mat());
      candidates.clear();
      float cell_max = 0.f;
      for (int y = y0; y < y1; ++y) {
        const float* resp = response.ptr<float>(y - region.y);
        const float* dil = dilated.ptr<float>(y - region.y);
        const uint8_t* blk = blocked.ptr<uint8_t>(y);
        for (int x = x0; x < x1; ++x) {
          const int rx = x - region.x;
          if (resp[rx] > options_.min_harris_response && resp[rx] >= dil[rx] && !blk[x]) {
            candidates.push_back({resp[rx], x, y});
            cell_max = std::max(cell_max, resp[rx]);
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
  // A new feature has no displacement of its own yet: it is predicted to
  // move as its neighbours did (at 10 px a frame, from its own position KLT
  // finds a wrong match for one new feature in six that the
  // forward-backward check does not catch).
  if (detected > 0) {
    const size_t live = tracks_.size() - size_t(detected);
    std::vector<Eigen::Vector2d> now, next;  // the live tracks, and where their flow takes them
    now.reserve(live);
    next.reserve(live);
    for (size_t i = 0; i < live; ++i) {
      now.push_back(tracks_[i].pixel);
      next.push_back(tracks_[i].pixel + tracks_[i].flow);
    }
    NeighbourFlow flow(now, next, options_.reacquire_neighbours);
    for (size_t i = live; i < tracks_.size(); ++i) {
      if (const auto f = flow.At(tracks_[i].pixel)) tracks_[i].flow = *f;
    }
  }
  if (stats != nullptr) stats->detected += detected;
  return detected;
}

}  // namespace uwscan::vo
