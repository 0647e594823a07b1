// Sparse feature tracking (thesis §5.2, "Feature Detection & Matching"): the
// image is split into a grid, each cell keeps its strongest Harris corners,
// and features are followed with pyramidal Lucas-Kanade (Bouguet 2001) with
// a forward-backward check. A mask (CV_8U, non-zero = ignore, e.g. the laser
// line of laser::DetectLaserLine) excludes pixels from detection and drops
// tracks that land on them.
//
// Track-to-track association across the line (thesis §5.5): a track lost on
// the mask (or by KLT, as the line enters its window) is kept dormant for a
// few frames, its position carried along with the flow of its neighbours;
// once that position is clear of the mask, KLT from the track's anchor image
// looks for it again and, if the forward-backward check holds, the track
// goes on under its old id, so the map point keeps its observations on both
// sides of the line instead of being cut into two tracks.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <unordered_map>
#include <vector>

#include "uwscan/vo/lucas_kanade.h"

namespace uwscan::vo {

struct FeatureTrackerOptions {
  int grid_cols = 8;
  int grid_rows = 6;
  int max_per_cell = 6;
  double harris_k = 0.04;
  double quality_level = 0.01;  // relative to the strongest corner in the cell
  double min_distance_px = 7.0;
  int klt_window_px = 21;
  int klt_pyramid_levels = 3;
  int klt_max_iterations = 30;
  // Levels of the pyramid above full resolution searched from each
  // track's predicted position (its last displacement carried on); tracks
  // lost from there are tracked again over all klt_pyramid_levels. A
  // negative value, or one not below klt_pyramid_levels, tracks every
  // feature over the full pyramid from its last position.
  int klt_predicted_levels = 0;
  double forward_backward_px = 0.5;  // max |p - backtrack(track(p))|
  double border_px = 8.0;            // tracks closer to the border are dropped
  // Minimum corner response in absolute terms (Harris on 8-bit images), so
  // that textureless or black frames yield no features rather than noise.
  double min_harris_response = 1e-7;
  // Drift-free tracking while the view changes little (a hovering
  // platform): every frame, tracks are refined by KLT directly from the
  // anchor image (the last keyframe) instead of only frame to frame, so
  // sub-pixel errors do not add up between keyframes.
  bool anchor_refinement = true;
  double anchor_max_correction_px = 1.0;
  // ... and from the anchor the track was first refined from, for up to
  // this many keyframes after it (0: always the last keyframe's) while the
  // view stays (SetAnchor's view_moved): each re-anchoring adds the
  // refinement's error of that moment, a track kept on its first anchor
  // does not collect them. On the tank hovers the tracks' median error went
  // 0.38 -> 0.25 px (BENCHMARKS.md, "First anchors"). The anchor images
  // stay in memory meanwhile: at most this many more pyramids.
  int anchor_keep_keyframes = 8;
  // Re-association of tracks lost on the mask or by KLT: frames a lost
  // track stays dormant (0 = off), neighbours whose median flow carries its
  // predicted position, and how far KLT may move it from that prediction.
  int max_dormant_frames = 20;
  int reacquire_neighbours = 8;
  double reacquire_max_offset_px = 3.0;
  double reacquire_min_correlation = 0.9;  // NCC of 11x11 patches, anchor vs found
  // The KLT's own options, from the klt_ ones above.
  LucasKanadeOptions Klt() const;
  void Check() const;
};

struct FeatureTrack {
  uint64_t id = 0;
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();
  int age = 0;            // frames tracked
  bool anchored = false;  // seen in the anchor image
  Eigen::Vector2d anchor_pixel = Eigen::Vector2d::Zero();
  Eigen::Vector2d flow = Eigen::Vector2d::Zero();  // displacement over the last frame
};

struct TrackingStats {
  int tracked = 0;      // survived this frame
  int lost_klt = 0;     // KLT failure or forward-backward error
  int lost_border = 0;  // left the image
  int lost_mask = 0;    // landed on masked pixels
  int detected = 0;     // new features
  int reacquired = 0;   // dormant tracks taken up again under their old id
  int predicted = 0;    // of those tracked, found from their predicted positions
};

class FeatureTracker {
 public:
  explicit FeatureTracker(const FeatureTrackerOptions& options = {});

  // Tracks the current features from the previous image into `gray`
  // (CV_8U). The first call only stores the image. `mask` may be empty.
  TrackingStats Track(const cv::Mat& gray, const cv::Mat& mask);
  // Detects new corners in cells holding fewer than max_per_cell features.
  int Detect(const cv::Mat& mask, TrackingStats* stats = nullptr);
  // Forgets all features and the previous image.
  void Reset();
  // Makes the current image the anchor of all current tracks; `mask` is
  // the mask Track received with it (empty: none). The refinement of a
  // track keeps its earlier anchor for up to anchor_keep_keyframes calls,
  // unless `view_moved` (a keyframe made for parallax: the patches' look
  // has changed more than the re-anchorings' error it would save).
  void SetAnchor(const cv::Mat& mask = cv::Mat(), bool view_moved = false);
  void RemoveTracks(const std::vector<uint64_t>& ids);
  // Moves each track to `where(track)`, if that gives a pixel (diagnostics:
  // the simulator's true tracks, OdometryOptions::true_track_pixel).
  void MoveTracks(const std::function<std::optional<Eigen::Vector2d>(const FeatureTrack&)>& where);

  const std::vector<FeatureTrack>& tracks() const { return tracks_; }
  int target_count() const {
    return options_.grid_cols * options_.grid_rows * options_.max_per_cell;
  }
  const FeatureTrackerOptions& options() const { return options_; }
  int num_dormant() const { return int(dormant_.size()); }

 private:
  using Pyramid = std::shared_ptr<const std::vector<cv::Mat>>;
  struct DormantTrack {
    FeatureTrack track;  // as last seen; track.pixel is carried by the flow
    Pyramid anchor;      // the image track.anchor_pixel refers to
    int frames = 0;      // frames dormant
  };
  FeatureTrackerOptions options_;
  LucasKanadeOptions klt_;  // from options_
  std::vector<FeatureTrack> tracks_;
  std::vector<DormantTrack> dormant_;
  Pyramid previous_pyramid_;
  Pyramid anchor_pyramid_;
  cv::Mat anchor_mask_;  // the anchor image's mask
  // Per track id, the anchor its refinement runs from
  // (anchor_keep_keyframes): image, position there, keyframes since.
  struct RefinementAnchor {
    Pyramid pyramid;
    Eigen::Vector2d pixel = Eigen::Vector2d::Zero();
    int keyframes = 0;
  };
  std::unordered_map<uint64_t, RefinementAnchor> refinement_anchors_;
  // Refines the frame-to-frame positions `current` (one per track) by KLT
  // from the anchor image, for the tracks seen there.
  void RefineFromAnchor(const std::vector<cv::Mat>& pyramid, std::vector<cv::Point2f>* current);
  // Tracks every feature from the previous image into `pyramid` (forward)
  // and back (at full resolution, from the previous position): `current`
  // receives the positions, `consistent` flags those that KLT found and
  // that came back to within forward_backward_px, `from_prediction` those
  // found from their predicted positions.
  void TrackForwardBackward(const std::vector<cv::Mat>& pyramid, std::vector<cv::Point2f>* current,
                            std::vector<uint8_t>* consistent,
                            std::vector<uint8_t>* from_prediction) const;
  void KeepDormant(const FeatureTrack& track);
  // Moves the dormant tracks with the flow of the live ones (`previous` ->
  // tracks_ positions), ages them and takes up those found again.
  void Reacquire(const std::vector<cv::Mat>& pyramid, const cv::Mat& mask,
                 const std::vector<Eigen::Vector2d>& flow_from,
                 const std::vector<Eigen::Vector2d>& flow_to, TrackingStats* stats);
  cv::Mat previous_gray_;
  uint64_t next_id_ = 1;
};

}  // namespace uwscan::vo
