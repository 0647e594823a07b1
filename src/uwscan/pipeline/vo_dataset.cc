#include "uwscan/pipeline/vo_dataset.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "uwscan/io/image.h"
#include "uwscan/io/rig_yaml.h"
#include "uwscan/util/error.h"

namespace uwscan {

VoDataset ReadVoDataset(const std::filesystem::path& dir) {
  UWS_CHECK(std::filesystem::is_directory(dir), dir.string(), ": not a dataset folder");
  VoDataset dataset;
  dataset.dir = dir;
  dataset.rig = ReadRigYaml(dir / "rig.yaml");
  const std::filesystem::path frames_csv = dir / "frames.csv";
  dataset.frames = ReadFramesCsv(frames_csv);
  UWS_CHECK(!dataset.frames.empty(), frames_csv.string(), ": no frames");
  if (std::filesystem::exists(dir / "groundtruth.tum")) {
    dataset.ground_truth = ReadTumTrajectory(dir / "groundtruth.tum");
  }
  return dataset;
}

cv::Mat ReadFrameImage(const VoDataset& dataset, const FrameRecord& frame) {
  const std::filesystem::path path = dataset.dir / frame.file;
  if (!std::filesystem::exists(path)) return cv::Mat();
  return cv::imread(path.string(), cv::IMREAD_UNCHANGED);
}

cv::Mat TrackingImage(const cv::Mat& raw, const std::string& bayer) {
  if (raw.empty()) return raw;
  if (raw.channels() == 1 && bayer != "none") {
    cv::Mat green;
    cv::extractChannel(DemosaicToBgr(raw, bayer), green, 1);
    return green;
  }
  if (raw.channels() == 3 || raw.channels() == 4) {
    cv::Mat green;
    cv::extractChannel(raw, green, 1);
    return green;
  }
  return raw;
}

}  // namespace uwscan
