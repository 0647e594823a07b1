#include "uwscan/calib/checkerboard.h"

#include <algorithm>
#include <exception>
#include <iomanip>
#include <mutex>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "uwscan/io/image.h"
#include "uwscan/io/rig_yaml.h"
#include "uwscan/util/error.h"
#include "uwscan/util/parallel.h"
#include "uwscan/util/progress.h"

namespace uwscan {

const char* CornerDetectorName(CornerDetector detector) {
  switch (detector) {
    case CornerDetector::kSectorBased:
      return "sb";
    case CornerDetector::kSectorBasedSubPix:
      return "sb-subpix";
    case CornerDetector::kClassic:
      return "classic";
  }
  return "?";
}

std::optional<CornerDetector> CornerDetectorFromName(const std::string& name) {
  for (CornerDetector d : {CornerDetector::kSectorBased, CornerDetector::kSectorBasedSubPix,
                           CornerDetector::kClassic}) {
    if (name == CornerDetectorName(d)) return d;
  }
  return std::nullopt;
}

namespace {

// Grey image of a mono or B G R image, optionally without one R G B channel.
cv::Mat Grey(const cv::Mat& image, int ignore_channel) {
  if (image.channels() != 3) return image;
  cv::Mat gray;
  if (ignore_channel < 0) {
    cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
    return gray;
  }
  std::vector<cv::Mat> bgr;
  cv::split(image, bgr);
  const int ignored = 2 - ignore_channel;  // B G R storage
  cv::addWeighted(bgr[(ignored + 1) % 3], 0.5, bgr[(ignored + 2) % 3], 0.5, 0.0, gray);
  return gray;
}

int CountLargerBoardCorners(const cv::Mat& image, const BoardSpec& board) {
  const cv::Mat gray = Grey(image, -1);
  std::vector<cv::Point2f> corners;
  const bool found = cv::findChessboardCornersSB(
      gray, cv::Size(board.cols, board.rows), corners,
      cv::CALIB_CB_EXHAUSTIVE | cv::CALIB_CB_LARGER | cv::CALIB_CB_NORMALIZE_IMAGE);
  return found ? static_cast<int>(corners.size()) : 0;
}

}  // namespace

void DetectionOptions::Check() const {
  UWS_CHECK(max_edge_width_px > 0.0, "max edge width must be positive");
  UWS_CHECK(ignore_channel >= -1 && ignore_channel <= 2,
            "ignore_channel must be -1 (none), 0, 1 or 2, got ", ignore_channel);
  UWS_CHECK(border_margin_px >= 0.0, "border margin must be >= 0");
}

BoardDetection DetectBoard(const cv::Mat& image, const BoardSpec& board,
                           const DetectionOptions& options) {
  options.Check();
  BoardDetection result;
  cv::Mat gray = Grey(image, options.ignore_channel);
  // Dim frames (underwater, short exposure) are stretched linearly to the
  // full range: a linear map keeps the corner positions unbiased, unlike
  // the detector's own histogram equalisation. A 16-bit frame is stretched
  // from its own samples, not from their top 8 bits: a 10- or 12-bit
  // camera's frames hold theirs in the low bits.
  const double full_scale = FullScale(gray);
  double lowest = 0.0, highest = 0.0;
  cv::minMaxLoc(gray, &lowest, &highest);
  if (highest > lowest && highest < 0.5 * full_scale) {
    gray.convertTo(gray, CV_8U, 255.0 / (highest - lowest), -lowest * 255.0 / (highest - lowest));
  } else if (gray.depth() != CV_8U) {
    gray.convertTo(gray, CV_8U, 255.0 / full_scale);
  }
  const cv::Size pattern(board.cols, board.rows);
  std::vector<cv::Point2f> corners;
  bool found;
  if (options.detector != CornerDetector::kClassic) {
    // No CALIB_CB_NORMALIZE_IMAGE at first: its histogram equalisation
    // bends the edge profiles and locks corners to the pixel grid by up to
    // 0.15 px (measured on rendered boards); it is the fallback only.
    const int flags = cv::CALIB_CB_EXHAUSTIVE | cv::CALIB_CB_ACCURACY;
    found = cv::findChessboardCornersSB(gray, pattern, corners, flags);
    if (!found) {
      found =
          cv::findChessboardCornersSB(gray, pattern, corners, flags | cv::CALIB_CB_NORMALIZE_IMAGE);
    }
    // SB's own sub-pixel estimate is robust to noise but biased under strong
    // perspective (rendered 40 deg views: focal length +0.2 %); the
    // Foerstner-type cornerSubPix on a small window is not.
    if (found && options.detector == CornerDetector::kSectorBasedSubPix &&
        static_cast<int>(corners.size()) == board.NumCorners()) {
      cv::cornerSubPix(
          gray, corners, cv::Size(5, 5), cv::Size(-1, -1),
          cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 0.001));
    }
  } else {
    found = cv::findChessboardCorners(gray, pattern, corners,
                                      cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE);
    if (found) {
      cv::cornerSubPix(
          gray, corners, cv::Size(5, 5), cv::Size(-1, -1),
          cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 0.001));
    }
  }
  if (!found || static_cast<int>(corners.size()) != board.NumCorners()) {
    result.reason = "board not found (partial, occluded, too blurred or not " +
                    std::to_string(board.cols) + "x" + std::to_string(board.rows) +
                    " inner corners)";
    return result;
  }
  result.corners = static_cast<int>(corners.size());
  const cv::Scalar sharpness = cv::estimateChessboardSharpness(gray, pattern, corners);
  result.edge_width_px = sharpness[0];
  result.contrast = sharpness[2] - sharpness[1];
  for (const cv::Point2f& c : corners) {
    if (c.x < options.border_margin_px || c.y < options.border_margin_px ||
        c.x > gray.cols - 1 - options.border_margin_px ||
        c.y > gray.rows - 1 - options.border_margin_px) {
      result.reason = "board touches the image border (partial view)";
      return result;
    }
  }
  if (result.edge_width_px >= 9999.0) {  // OpenCV's "could not measure"
    result.reason = "sharpness not measurable along the board edges (wrong --board size?)";
    return result;
  }
  if (result.edge_width_px > options.max_edge_width_px) {
    result.reason =
        internal::Concat(std::setprecision(4), "blurred: edge width ", result.edge_width_px,
                         " px > ", options.max_edge_width_px, " px (--max-edge-width)");
    return result;
  }
  if (result.contrast < options.min_contrast) {
    result.reason = internal::Concat(std::setprecision(4), "low contrast: ", result.contrast,
                                     " grey levels < ", options.min_contrast, " (--min-contrast)");
    return result;
  }
  result.found = true;
  for (const cv::Point2f& c : corners) result.points.emplace_back(c.x, c.y);
  return result;
}

FolderDetection DetectBoardsInFolder(const std::filesystem::path& folder, const BoardSpec& board,
                                     const DetectionOptions& options) {
  namespace fs = std::filesystem;
  const std::vector<fs::path> files = ListImageFiles(folder);
  FolderDetection result;
  result.set.board = board;
  // Raw Bayer frames of a dataset (its rig.yaml beside or above the folder)
  // are demosaicked first: the mosaic read as grey is a pixel-level
  // checkerboard of its own.
  std::string bayer = "none";
  for (const fs::path& rig_path : {folder / "rig.yaml", folder.parent_path() / "rig.yaml"}) {
    std::error_code error;
    if (fs::exists(rig_path, error)) {
      const Rig rig = ReadRigYaml(rig_path);
      if (!rig.cameras.empty()) bayer = rig.cameras.front().bayer;
      break;
    }
  }
  // The detector is most of a calibration's time: the images on all cores,
  // each alone; errors are then said in the images' order.
  struct Read {
    cv::Size size;
    BoardDetection detection;
    std::exception_ptr error;
  };
  std::vector<Read> reads(files.size());
  ProgressBar progress("boards in " + folder.string(), static_cast<long>(files.size()),
                       options.progress);
  std::mutex progress_mutex;
  long done = 0;
  ParallelFor(static_cast<int>(files.size()), MachineThreads(), 1, [&](int i) {
    Read& read = reads[i];
    try {
      cv::Mat image = cv::imread(files[i].string(), cv::IMREAD_UNCHANGED);
      UWS_CHECK(!image.empty(), files[i].string(), ": cannot read the image");
      PrepareFrame(&image, 16, files[i]);  // an alpha channel dropped
      image = DemosaicToBgr(image, bayer);
      read.size = image.size();
      read.detection = DetectBoard(image, board, options);
    } catch (...) {
      read.error = std::current_exception();
    }
    const std::lock_guard<std::mutex> lock(progress_mutex);
    progress.Update(++done);
  });
  progress.Finish();
  for (size_t i = 0; i < files.size(); ++i) {
    Read& read = reads[i];
    if (read.error) std::rethrow_exception(read.error);
    if (result.set.width == 0) {
      result.set.width = read.size.width;
      result.set.height = read.size.height;
    }
    UWS_CHECK(read.size.width == result.set.width && read.size.height == result.set.height,
              files[i].string(), ": image is ", read.size.width, "x", read.size.height, " but ",
              files.front().string(), " is ", result.set.width, "x", result.set.height,
              "; all images must have the same size");
    BoardDetection& detection = read.detection;
    detection.name = files[i].filename().string();
    if (detection.found) result.set.views.push_back({detection.name, detection.points});
    result.images.push_back(std::move(detection));
  }
  // A board spec smaller than the real board still finds sub-boards (valid
  // geometry, but a user error): probe a few images with CALIB_CB_LARGER.
  std::vector<size_t> probes;
  for (size_t i = 0; i < files.size() && probes.size() < 3; ++i) {
    if (result.images[i].found || result.set.views.empty()) probes.push_back(i);
  }
  std::vector<int> probe_corners(probes.size());
  ParallelFor(static_cast<int>(probes.size()), MachineThreads(), 1, [&](int p) {
    probe_corners[p] = CountLargerBoardCorners(cv::imread(files[probes[p]].string()), board);
  });
  const int probed = static_cast<int>(probes.size());
  const int larger = static_cast<int>(std::count_if(probe_corners.begin(), probe_corners.end(),
                                                    [&](int n) { return n > board.NumCorners(); }));
  UWS_CHECK(larger < 2, folder.string(), ": ", larger, " of ", probed,
            " probed image(s) show a board with more inner corners than ", board.cols, "x",
            board.rows, "; check --board (inner corners, COLSxROWS)");
  // Boards found but none kept: say why, not that the board is not there.
  const auto has_corners = [](const BoardDetection& d) { return d.corners > 0; };
  const auto rejected = std::find_if(result.images.begin(), result.images.end(), has_corners);
  UWS_CHECK(!result.set.views.empty() || rejected == result.images.end(), folder.string(), ": the ",
            board.cols, "x", board.rows, " board was found in ",
            std::count_if(result.images.begin(), result.images.end(), has_corners), " of ",
            files.size(), " image(s) but none was kept (", rejected->name, ": ", rejected->reason,
            "); check the images, or --max-edge-width and --min-contrast");
  UWS_CHECK(!result.set.views.empty(), folder.string(), ": no ", board.cols, "x", board.rows,
            " board found in any of ", files.size(),
            " image(s); check --board (inner corners, COLSxROWS) and the images (first: ",
            result.images.front().reason, ")");
  return result;
}

}  // namespace uwscan
