#include "uwscan/io/image.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <vector>

#include "uwscan/io/png.h"
#include "uwscan/util/atomic_file.h"
#include "uwscan/util/error.h"

namespace uwscan {

void WritePng(const std::filesystem::path& path, const cv::Mat& image, int compression) {
  UWS_CHECK(!image.empty(), path.string(), ": empty image");
  UWS_CHECK(image.depth() == CV_8U || image.depth() == CV_16U, path.string(),
            ": PNG needs 8- or 16-bit pixels");
  UWS_CHECK(image.channels() == 1 || image.channels() == 3, path.string(),
            ": PNG needs 1 or 3 channels");
  std::vector<uchar> buffer;
  UWS_CHECK(cv::imencode(".png", image, buffer, {cv::IMWRITE_PNG_COMPRESSION, compression}),
            path.string(), ": PNG encoding failed");
  AtomicFile file(path, /*binary=*/true);
  file.stream().write(reinterpret_cast<const char*>(buffer.data()),
                      static_cast<std::streamsize>(buffer.size()));
  file.Commit();
}

cv::Mat ReadImage(const std::filesystem::path& path) {
  thread_local std::vector<uint8_t> bytes;  // reused: frames are read one after another
  {
    std::ifstream file(path, std::ios::binary | std::ios::ate);
    UWS_CHECK(file.good(), path.string(), ": cannot read image (cannot open the file)");
    const std::streamoff size = file.tellg();
    UWS_CHECK(size > 0, path.string(), ": cannot read image (empty file)");
    bytes.resize(size_t(size));
    file.seekg(0);
    file.read(reinterpret_cast<char*>(bytes.data()), size);
    UWS_CHECK(file.good(), path.string(), ": cannot read image (read error)");
  }
  if (HasPngSignature(bytes)) {
    if (std::optional<cv::Mat> image = DecodePng(bytes, path.string())) return *image;
  }
  cv::Mat image = cv::imdecode(bytes, cv::IMREAD_UNCHANGED);
  UWS_CHECK(!image.empty(), path.string(), ": cannot read image");
  return image;
}

std::string ImageTypeName(int type) {
  const int depth = CV_MAT_DEPTH(type);
  const std::string bits = depth == CV_8U || depth == CV_8S     ? "8-bit"
                           : depth == CV_16U || depth == CV_16S ? "16-bit"
                           : depth == CV_32F                    ? "32-bit float"
                           : depth == CV_64F                    ? "64-bit float"
                                                                : "32-bit";
  return std::to_string(CV_MAT_CN(type)) + "-channel " + bits;
}

double FullScale(const cv::Mat& image) { return image.depth() == CV_16U ? 65535.0 : 255.0; }

namespace {

// The means of a single-channel 8- or 16-bit image's four 2x2 pixel phases
// (row-major: (0,0), (0,1), (1,0), (1,1)) as fractions of full scale; none
// for other images and ones under 16x16.
std::optional<std::array<double, 4>> PhaseMeans(const cv::Mat& image) {
  if (image.channels() != 1 || image.cols < 16 || image.rows < 16) return std::nullopt;
  if (image.depth() != CV_8U && image.depth() != CV_16U) return std::nullopt;
  const double full_scale = FullScale(image);
  double sum[2][2] = {{0, 0}, {0, 0}};
  for (int y = 0; y < image.rows; ++y) {
    for (int x = 0; x < image.cols; ++x) {
      sum[y % 2][x % 2] +=
          image.depth() == CV_8U ? image.at<uint8_t>(y, x) : image.at<uint16_t>(y, x);
    }
  }
  const auto mean = [&](int y, int x) {  // the phase's pixels: odd sizes have fewer in the last
    return sum[y][x] / (double((image.rows - y + 1) / 2) * double((image.cols - x + 1) / 2)) /
           full_scale;
  };
  return std::array<double, 4>{mean(0, 0), mean(0, 1), mean(1, 0), mean(1, 1)};
}

// How many times the brighter of two phase means is the darker, both
// floored at 1 % of full scale (a dark phase's mean is mostly noise).
double PhaseRatio(double a, double b) {
  a = std::max(a, 0.01);
  b = std::max(b, 0.01);
  return std::max(a, b) / std::min(a, b);
}

}  // namespace

double MosaicPhaseRatio(const cv::Mat& image) {
  const auto means = PhaseMeans(image);
  if (!means) return std::nan("");
  const double brightest = *std::max_element(means->begin(), means->end());
  const double darkest = *std::min_element(means->begin(), means->end());
  if (brightest < 0.02) return std::nan("");
  return brightest / std::max(darkest, 0.01);
}

std::string OtherBayerDiagonal(const cv::Mat& raw, const std::string& bayer) {
  const auto means = PhaseMeans(raw);
  if (!means || bayer == "none") return "";
  // rggb and bggr have their greens at (0,1) and (1,0), grbg and gbrg at
  // (0,0) and (1,1). A Gr/Gb imbalance is a few percent.
  const bool greens_off_diagonal = bayer == "rggb" || bayer == "bggr";
  const double said = greens_off_diagonal ? PhaseRatio((*means)[1], (*means)[2])
                                          : PhaseRatio((*means)[0], (*means)[3]);
  const double other = greens_off_diagonal ? PhaseRatio((*means)[0], (*means)[3])
                                           : PhaseRatio((*means)[1], (*means)[2]);
  if (said > 1.5 && other < 1.2) return greens_off_diagonal ? "grbg or gbrg" : "rggb or bggr";
  return "";
}

void ScaleLowBitSamples(cv::Mat* image, int sample_bits, const std::filesystem::path& file) {
  if (sample_bits == 0 || sample_bits == 16 || image->empty()) return;
  UWS_CHECK(sample_bits >= 9 && sample_bits < 16, "sample bits must be 9-16 (got ", sample_bits,
            ")");
  UWS_CHECK(image->depth() == CV_16U, file.string(), ": a ", ImageTypeName(image->type()),
            " frame, but ", sample_bits, "-bit samples are looked for in 16-bit ones");
  double brightest = 0;
  cv::minMaxLoc(image->reshape(1), nullptr, &brightest);
  const int limit = (1 << sample_bits) - 1;
  UWS_CHECK(brightest <= limit, file.string(), ": a sample of ", brightest, " does not fit ",
            sample_bits, " bits (at most ", limit, ")");
  *image *= double(1 << (16 - sample_bits));
}

void PrepareFrame(cv::Mat* image, int sample_bits, const std::filesystem::path& file) {
  if (image->channels() == 4) cv::cvtColor(*image, *image, cv::COLOR_BGRA2BGR);
  UWS_CHECK(image->empty() || image->channels() == 1 || image->channels() == 3, file.string(),
            ": a ", ImageTypeName(image->type()),
            " image: frames are grey or raw Bayer (1 channel) or colour (3, or 4 with alpha)");
  ScaleLowBitSamples(image, sample_bits, file);
}

int LowSampleBits(const cv::Mat& image) {
  if (image.empty() || image.depth() != CV_16U) return 0;
  const cv::Mat samples = image.reshape(1);
  double brightest = 0;
  cv::minMaxLoc(samples, nullptr, &brightest);
  int bits = 0;
  for (const int candidate : {10, 12}) {
    if (brightest < (1 << candidate)) {
      bits = candidate;
      break;
    }
  }
  if (bits == 0 || brightest == 0) return 0;
  for (int y = 0; y < samples.rows; ++y) {
    const uint16_t* row = samples.ptr<uint16_t>(y);
    for (int x = 0; x < samples.cols; ++x) {
      if (row[x] % 4 != 0) return bits;
    }
  }
  return 0;  // full-range samples of 12 bits or fewer, dark
}

FrameDoubts InspectFrame(const cv::Mat& image, const std::filesystem::path& file,
                         const std::string& bayer, bool from_rig, int sample_bits) {
  FrameDoubts doubts;
  doubts.file = file;
  doubts.bayer = bayer;
  doubts.from_rig = from_rig;
  const double ratio = bayer == "none" ? MosaicPhaseRatio(image) : std::nan("");
  if (ratio > kMosaicPhaseRatio) doubts.mosaic_phase_ratio = ratio;
  if (sample_bits == 16) doubts.low_sample_bits = LowSampleBits(image);
  doubts.other_bayer = OtherBayerDiagonal(image, bayer);
  doubts.lit_share = LitShare(image);
  return doubts;
}

double LitShare(const cv::Mat& image) {
  if (image.empty()) return 1.0;
  cv::Mat lit;
  cv::compare(image.reshape(1), 0.02 * FullScale(image), lit, cv::CMP_GT);
  return static_cast<double>(cv::countNonZero(lit)) / static_cast<double>(lit.total());
}

std::vector<std::string> FrameDoubts::Warnings() const {
  std::vector<std::string> warnings;
  if (!other_bayer.empty()) {
    warnings.push_back(file.string() + ": rig.yaml says bayer " + bayer +
                       ", but this raw frame's green samples are on the other diagonal (the two "
                       "phases it calls green differ by more than half, the other two agree): "
                       "the pattern is " +
                       other_bayer +
                       "; set it in rig.yaml (OpenCV names a pattern by its second row: its "
                       "BayerBG is rggb)");
  }
  if (low_sample_bits > 0) {
    const std::string bits = std::to_string(low_sample_bits);
    warnings.push_back(file.string() + ": a 16-bit frame whose samples all fit in " + bits +
                       " bits: it looks like a " + bits +
                       "-bit camera's frame saved unpacked, read as 16-bit and " +
                       std::to_string(1 << (16 - low_sample_bits)) +
                       " times darker than the features' and the clipping's thresholds take it "
                       "to be; give --sample-bits " +
                       bits);
  }
  // Samples in the low bits are dark for a reason already said.
  if (lit_share < kBlackFrameLitShare && low_sample_bits == 0) {
    char share[32];
    std::snprintf(share, sizeof share, "%.3g", 100.0 * lit_share);
    warnings.push_back(file.string() + ": a black frame: " + share +
                       " % of its samples are above 2 % of full scale (a lens cap, the lights "
                       "off, or an exposure or gain far too low): no texture to track and no "
                       "laser line to find");
  }
  if (mosaic_phase_ratio > 0) {
    char factor[32];
    std::snprintf(factor, sizeof factor, "%.2f", mosaic_phase_ratio);
    warnings.push_back(
        file.string() + ": a single-channel frame whose 2x2 pixel phases differ in mean by a " +
        "factor of " + factor + ": it looks like a raw Bayer mosaic, but the camera is taken " +
        "for a mono one (bayer: none), and its colours are read as one grey image; " +
        (from_rig ? "set the camera's bayer (rggb, bggr, grbg or gbrg) in rig.yaml"
                  : "give --rig with the camera's bayer (rggb, bggr, grbg or gbrg)"));
  }
  return warnings;
}

void CheckSampleBitsOption(int sample_bits) {
  UWS_USAGE_CHECK(sample_bits >= 9 && sample_bits <= 16,
                  "--sample-bits must be 9-16 (16: as stored), got ", sample_bits);
}

cv::Mat DemosaicToBgr(const cv::Mat& raw, const std::string& bayer) {
  if (raw.empty() || raw.channels() != 1 || bayer == "none") return raw;
  // OpenCV names Bayer codes by the second row's pattern start: RGGB is BayerBG.
  const int code = bayer == "rggb"   ? cv::COLOR_BayerBG2BGR
                   : bayer == "bggr" ? cv::COLOR_BayerRG2BGR
                   : bayer == "grbg" ? cv::COLOR_BayerGB2BGR
                                     : cv::COLOR_BayerGR2BGR;
  cv::Mat bgr;
  cv::cvtColor(raw, bgr, code);
  return bgr;
}

namespace {

std::vector<std::filesystem::path> ImagesIn(const std::filesystem::path& folder) {
  std::vector<std::filesystem::path> images;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(folder, error)) {
    // Hidden files are not frames: macOS's "._NAME.png" beside each image
    // copied to a USB disk, an editor's backup.
    if (!entry.is_regular_file(error) || entry.path().filename().string().front() == '.') continue;
    std::string ext = entry.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".tif" || ext == ".tiff" ||
        ext == ".pgm" || ext == ".ppm" || ext == ".bmp") {
      images.push_back(entry.path());
    }
  }
  std::sort(images.begin(), images.end());
  return images;
}

}  // namespace

std::vector<std::filesystem::path> ListImageFiles(const std::filesystem::path& folder) {
  std::error_code error;
  UWS_CHECK(std::filesystem::is_directory(folder, error), folder.string(), ": not a folder");
  std::vector<std::filesystem::path> images = ImagesIn(folder);
  if (images.empty() && std::filesystem::is_directory(folder / "frames", error) &&
      !ImagesIn(folder / "frames").empty()) {
    UWS_THROW(folder.string(), ": no images (png, jpg, tif, pgm, ppm, bmp) in the folder; it is a ",
              "dataset, whose images are in ", (folder / "frames").string());
  }
  UWS_CHECK(!images.empty(), folder.string(),
            ": no images (png, jpg, tif, pgm, ppm, bmp) in the folder");
  return images;
}

}  // namespace uwscan
