// The further cameras of a several-camera dataset (sim --pods 2, thesis
// §6.5): each with its own laser, its profiles placed with the main
// camera's trajectory, interpolated to their timestamps, and the rig's
// extrinsics. A frame is placed as soon as the main trajectory has reached
// its time, not after the main camera's whole scan, so that a live run's
// cloud grows from every camera at once.
#pragma once

#include <chrono>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "uwscan/geometry/rigid3d.h"
#include "uwscan/io/dataset.h"
#include "uwscan/io/tum.h"
#include "uwscan/laser/profile.h"
#include "uwscan/pipeline/reconstruct.h"
#include "uwscan/sensor/rig.h"

namespace uwscan {

// The frames of `dataset`'s frames.csv, the first `max_frames` if > 0.
// Throws uwscan::Error naming the file if there are none or an image is
// missing (said before the scan, not minutes into it).
std::vector<FrameRecord> ReadFrames(const std::filesystem::path& dataset, int max_frames);

// Camera NAME's images in DATASET/NAME/, a dataset of its own whose rig
// lists that camera and its laser first.
struct OtherCamera {
  std::filesystem::path folder;
  std::vector<FrameRecord> frames;
  Rig rig;                   // as DATASET/NAME/rig.yaml has it
  Rigid3d main_from_camera;  // from the main camera, through the rig
};

// Every camera of `rig` but `main_camera` with a folder of its own in
// `dataset`. Throws uwscan::Error naming the file on a bad one.
std::vector<OtherCamera> FindOtherCameras(const std::filesystem::path& dataset, const Rig& rig,
                                          size_t main_camera, int max_frames);

// The further cameras' frames, read ahead on their own threads from the
// start (paced as a live camera delivers them with `live_from`, dropped
// past `max_lag_s` as the main camera's: FrameReader), their lines found
// and their profiles placed on the main camera's poses.
class OtherCameraStages {
 public:
  // A profile into the clouds: placed with `pose`, and with `unmoved`.
  using AddProfile = std::function<void(const laser::Profile& profile, int frame,
                                        const Rigid3d& pose, const Rigid3d& unmoved)>;
  // Called for each frame taken, placed or not (its timestamp).
  using FrameDone = std::function<void(double timestamp_s, bool placed)>;

  // `job` and `others` must outlive the stages.
  OtherCameraStages(const ReconstructJob& job, const std::vector<OtherCamera>& others,
                    std::optional<std::chrono::steady_clock::time_point> live_from,
                    std::optional<double> max_lag_s);
  ~OtherCameraStages();
  OtherCameraStages(const OtherCameraStages&) = delete;
  OtherCameraStages& operator=(const OtherCameraStages&) = delete;

  // Places each camera's frames up to the last of `main_poses` (the main
  // camera's placed poses, in time order), or all of them with `all` (the
  // main scan is over): each with the main pose interpolated to its time
  // (none beyond `max_gap_s` outside the trajectory), moved to the camera.
  // A frame's pose is the same whenever it is placed: the main poses
  // before and after its time are both placed by then.
  void Place(const std::vector<StampedPose>& main_poses, const Rigid3d& first_main_pose,
             double max_gap_s, bool all, const AddProfile& add_profile,
             const FrameDone& frame_done);
  // Finishes the cameras' trajectories (TumWriter::Finish) and adds their
  // reports (and their line stages' counts) to `report`; Commit() renames
  // the trajectories into place.
  void Finish(ReconstructReport* report);
  void Commit();
  double seconds_waiting() const;

 private:
  struct Stage;
  std::vector<std::unique_ptr<Stage>> stages_;
};

}  // namespace uwscan
