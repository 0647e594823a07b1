// Controller of `uwscan laser detect`: streams images through the laser
// detector, writes detections (and optionally profiles and overlays).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "uwscan/io/image.h"
#include "uwscan/laser/detector.h"
#include "uwscan/sensor/rig.h"

namespace uwscan {

struct LaserDetectJob {
  // Either a dataset folder (rig.yaml, frames.csv with servo angles, frames/)
  // or a folder of images (all of them, sorted by name) with an optional rig.
  std::filesystem::path dataset_dir;
  std::filesystem::path images_dir;
  std::optional<std::filesystem::path> rig_path;
  std::string camera_name;                            // default: the first camera
  std::string laser_name;                             // default: the first laser
  std::filesystem::path detections_csv;               // frame,u,v,channel,strength
  std::optional<std::filesystem::path> profiles_csv;  // frame,x,y,z (needs a rig with a laser)
  std::optional<std::filesystem::path> overlay_dir;
  std::string scan = "auto";     // rows | cols | auto (from the rig)
  std::string channel = "auto";  // red | green | blue | auto (laser wavelength)
  std::string albedo = "auto";   // red | green | blue | none | auto (laser::AlbedoChannelFor)
  laser::DetectorOptions detector;
  int sample_bits = 16;  // ReconstructJob::sample_bits
  bool quiet = false;
  void Check() const;
};

struct LaserDetectSummary {
  int frames = 0;
  int frames_without_line = 0;
  int frames_laser_off = 0;  // skipped: frames.csv says the laser was off (interleaved scans)
  int unreadable_frames = 0;
  long points = 0;
  long profile_points = 0;
  long grazing_points = 0;               // left out of the profiles (laser::kMaxRangeErrorPerPixel)
  long missed_points = 0;                // ... as their ray met the light sheet nowhere
  bool laser_pose_inverse_fits = false;  // laser::InverseLaserPoseFits on the first line
  // Frames whose scene is at full scale in the laser's colour on at least
  // laser::kClippedFrameShare of the image away from the line, and the
  // share over all frames (laser::MeasureClipping).
  int frames_with_clipped_scene = 0;
  double clipped_scene_share = 0.0;
  FrameDoubts first_frame;  // of the first frame read
  // The first frame read showed the line in another colour than the one
  // looked in (laser::LaserColourWarning); empty if not.
  std::string laser_colour_warning;
  double seconds = 0.0;
};

// Whether to scan along rows: true when the laser line runs more vertically
// than horizontally in the image (projected sheet points at 1-3 m).
bool LaserLineIsVertical(const Camera& camera, const Rigid3d& camera_from_laser);

LaserDetectSummary RunLaserDetect(const LaserDetectJob& job);

}  // namespace uwscan
