// Where the reconstruction takes each frame's pose from: the self-referenced
// visual odometry, or an external trajectory (INS, ground truth) for
// comparison (`--poses FILE`).
#pragma once

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "uwscan/io/tum.h"
#include "uwscan/laser/detector.h"
#include "uwscan/laser/profile.h"

namespace uwscan::fusion {

// The part of a frame's pose estimation that needs no other frame (the
// image as the provider tracks it, the line mask it ignores), made ahead on
// the image-reading thread (PoseProvider::PrepareAhead).
struct PreparedFrame {
  cv::Mat image;
  cv::Mat mask;           // empty: no line, or not found yet (has_mask false)
  bool has_mask = false;  // the mask was made from the frame's line
  int variant = 0;        // the provider's choice it was made with
  // The image is the mean of this many frames, from first_averaged to the
  // frame's own (SelfReferencedOptions::average_skipped_frames); 1: the
  // frame's alone.
  int averaged_frames = 1;
  int first_averaged = -1;
};

// Everything the pose estimation of one frame may use.
struct FrameInput {
  int index = 0;
  double timestamp_s = 0.0;
  cv::Mat image;                                // as stored (raw Bayer, mono or BGR)
  const laser::Detection* detection = nullptr;  // with the line mask
  const laser::Profile* profile = nullptr;      // camera-frame laser points (metric)
  const PreparedFrame* prepared = nullptr;      // PrepareAhead's, if it ran
};

struct PoseUpdate {
  int frame = 0;
  Rigid3d world_from_camera;
};

// Frames go in one by one; poses come out as they become known, possibly
// for earlier frames (a provider may hold frames back, e.g. until its map
// is initialised). A frame whose pose never comes has no pose (its profile
// is left out, never placed at a wrong pose).
class PoseProvider {
 public:
  virtual ~PoseProvider() = default;
  virtual std::vector<PoseUpdate> Add(const FrameInput& frame) = 0;
  // End of the sequence: poses still held back.
  virtual std::vector<PoseUpdate> Finish() { return {}; }
  virtual std::string Name() const = 0;
  // Statistics for report.json.
  virtual nlohmann::json Details() const { return nlohmann::json::object(); }
  // Raw poses estimated by the last Add, before any smoothing or delay (for
  // predictions such as the laser motion filter's; the poses that place the
  // profiles are those Add and Finish return).
  virtual std::vector<PoseUpdate> Preliminary() const { return {}; }
  // Whether PrepareAhead does anything. It may then run on another thread,
  // concurrently with Add, for frames not yet added (their detection set
  // if their line is found already), called for the frames in order; Add
  // takes its result in FrameInput::prepared.
  virtual bool PreparesAhead() const { return false; }
  virtual PreparedFrame PrepareAhead(const FrameInput& /*frame*/) const { return {}; }
};

// Poses from a TUM trajectory, interpolated at the frame's timestamp
// (linear in translation, slerp in rotation), as an INS at 50 Hz would be
// used with a 144 Hz camera. Frames outside the trajectory's time span by
// more than `max_extrapolation_s`, or inside one of its gaps (begin, end:
// uwscan's `# gap` comments, where the odometry that wrote it had no pose),
// get no pose.
class TrajectoryPoseProvider : public PoseProvider {
 public:
  TrajectoryPoseProvider(std::vector<StampedPose> poses, std::string name,
                         double max_extrapolation_s = 0.05,
                         std::vector<std::pair<double, double>> gaps = {});
  std::vector<PoseUpdate> Add(const FrameInput& frame) override;
  std::string Name() const override { return name_; }

 private:
  std::vector<StampedPose> poses_;
  std::string name_;
  double max_extrapolation_s_;
  std::vector<std::pair<double, double>> gaps_;
};

// Interpolation used by TrajectoryPoseProvider (exposed for tests).
std::optional<Rigid3d> InterpolatePose(const std::vector<StampedPose>& poses, double timestamp_s,
                                       double max_extrapolation_s);

// How far a set of poses moved between two estimates, rms over the poses:
// the camera's displacement and its turn.
struct PoseChange {
  double moved_m = 0.0, turned_deg = 0.0;
};
// The rms change of the poses both lists have (at the same positions);
// none if they share none.
std::optional<PoseChange> RmsPoseChange(const std::vector<std::optional<Rigid3d>>& before,
                                        const std::vector<std::optional<Rigid3d>>& after);

}  // namespace uwscan::fusion
