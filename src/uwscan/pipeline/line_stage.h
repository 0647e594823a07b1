// One camera's laser stage of `uwscan reconstruct`: the line in each frame
// (the sweep filter on servo scans, the motion filter with a fixed laser,
// difference images on interleaved scans, albedo edges dropped) and its
// profile, with the counters and timings of the report.
#pragma once

#include <filesystem>
#include <optional>
#include <utility>
#include <vector>

#include "uwscan/io/dataset.h"
#include "uwscan/laser/detector.h"
#include "uwscan/laser/motion_filter.h"
#include "uwscan/laser/profile.h"
#include "uwscan/laser/sweep_filter.h"
#include "uwscan/pipeline/reconstruct.h"

namespace uwscan {

// Whether the frames' laser angles change (a servo sweep) rather than stay
// (a laser fixed to the platform, or no angles).
bool LaserSweeps(const std::vector<FrameRecord>& frames);

class LineStage {
 public:
  // `camera`, `laser`, `frames`, `job` and `report` must outlive the stage.
  LineStage(const ReconstructJob& job, std::filesystem::path dataset, const Camera& camera,
            const LineProjector& laser, const Rigid3d& camera_from_laser,
            const std::vector<FrameRecord>& frames, ReconstructReport* report);

  // The pose of a frame, once known (the motion filter predicts from them).
  void SetPose(int frame, const Rigid3d& world_from_camera);
  // True if Process needs the poses of the frames before (the motion
  // filter); otherwise frames may be processed ahead of their poses, on
  // another thread, one at a time and in order.
  bool NeedsPoses() const { return motion_filter_.has_value(); }

  const laser::DetectorOptions& detector() const { return detector_; }
  int ScanLines() const { return detector_.scan_rows ? camera_.height : camera_.width; }
  // With ReconstructJob::line_window_px, every this many frames the scan
  // lines are searched whole again (a line that appeared far from the
  // last one on a scan line that has it, or one a window followed astray).
  static constexpr int kWholeScanEvery = 10;
  // A point found on a scan line without a prior continues the line when
  // near the prior of a scan line this close.
  static constexpr int kPriorNeighbourLines = 32;

  // Frame i's image as the pipeline takes it (PrepareFrame with
  // ReconstructJob::sample_bits). Throws uwscan::Error naming the file.
  cv::Mat ReadFrameImage(size_t i) const;
  // Frame i of the sequence, its image as read: the line and its profile.
  // Throws uwscan::Error (naming the file) if the image has the wrong size,
  // or other channels or bit depth than the first frame's.
  void Process(size_t i, const cv::Mat& image, laser::Detection* detection,
               laser::Profile* profile);

 private:
  laser::Detection Detect(const cv::Mat& image, const FrameRecord& record);
  // Whether the line found with line_prior_ has points off it (something
  // that appeared; then the frame is detected again on whole scan lines).
  bool OffThePrior(const laser::Detection& detection) const;
  // Interleaved scans, at the first laser-off frame after a laser-on one:
  // whether the line shows far more clearly in its difference to that
  // frame than the other way round (frames.csv's laser_on inverted).
  void CheckLaserOn(size_t i);
  // The first frame with the laser on, where its colour (rig.yaml's
  // wavelength_nm) shows hardly a line: whether another colour shows one.
  void CheckLaserColour(const cv::Mat& image, const laser::Detection& detection);
  // A detected point's scan line and position along it.
  std::pair<int, float> OnScanLine(const laser::LaserPoint& p) const;
  void StartSweepFilter();
  // The first frame: its type, which every frame must have, and what it
  // says of how the frames are read (ReconstructReport::first_frame).
  void InspectFirstFrame(const cv::Mat& image, const std::filesystem::path& file);

  const ReconstructJob& job_;
  std::filesystem::path dataset_;
  const Camera& camera_;
  const LineProjector& laser_;
  Rigid3d camera_from_laser_;
  const std::vector<FrameRecord>& frames_;
  ReconstructReport* report_;
  laser::DetectorOptions detector_;
  std::optional<laser::SweepFilter> sweep_filter_;
  std::optional<laser::MotionFilter> motion_filter_;
  bool windowed_ = false;  // ReconstructJob::line_window_px applies
  // The last detection's line per scan line (interval of positions; NaN
  // where none), the scan lines it is on, and the frames detected with a
  // prior since the last whole scan.
  std::vector<std::pair<float, float>> line_prior_;
  int prior_lines_ = 0;
  int windowed_frames_ = 0;
  cv::Mat dark_image_;  // the last laser-off frame of an interleaved scan, and its index
  size_t dark_frame_ = 0;
  int first_image_type_ = -1;          // the first frame's OpenCV type, which every frame must have
  bool laser_pose_checked_ = false;    // laser::InverseLaserPoseFits ran (first frame with a line)
  bool laser_colour_checked_ = false;  // CheckLaserColour ran (first frame with the laser on)
  // Interleaved scans: the first laser-on frame's image and line points
  // (after a laser-off one), until CheckLaserOn ran on the frame after it.
  bool laser_on_checked_ = false;
  cv::Mat lit_image_;
  size_t lit_frame_ = 0, lit_points_ = 0;
};

// Adds what a further camera's stage wrote to its own report (each
// camera's stage runs on its own reading thread, in parallel with the
// main camera's, so each writes a report of its own) to `report`: counts
// and times summed; what each camera checks once (the laser's pose and
// colour, its switching, the features' colour) kept from the main camera
// where it found something, else taken from the further camera.
void AddFurtherCameraLineCounts(const ReconstructReport& further, ReconstructReport* report);

}  // namespace uwscan
