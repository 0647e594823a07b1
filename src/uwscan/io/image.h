// Image files: PNG (8- or 16-bit, 1 or 3 channels, raw Bayer mosaics stored
// as one channel) written atomically, read back unchanged.
#pragma once

#include <filesystem>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace uwscan {

// Writes CV_8U/CV_16U with 1 or 3 channels (B G R) as PNG via a temporary
// name; throws uwscan::Error naming the file.
void WritePng(const std::filesystem::path& path, const cv::Mat& image, int compression = 3);
// Demosaics a raw Bayer frame (`bayer` as in rig.yaml: rggb | bggr | grbg |
// gbrg) to B G R; images with 3 channels or bayer "none" come back as they are.
cv::Mat DemosaicToBgr(const cv::Mat& raw, const std::string& bayer);

// Reads any image unchanged (bit depth and channels kept).
cv::Mat ReadImage(const std::filesystem::path& path);
// An OpenCV image type in words: "1-channel 8-bit", "3-channel 16-bit".
std::string ImageTypeName(int type);

// The ratio of the brightest to the darkest mean of a single-channel
// image's four 2x2 pixel phases (the darkest floored at 1 % of full scale):
// about 1 for a mono camera's image, the colours' ratio for a raw Bayer
// mosaic, whose phases are different colours. NaN for other images, and for
// ones too small (under 16x16) or too dark (brightest phase under 2 % of
// full scale) to say.
double MosaicPhaseRatio(const cv::Mat& image);
// A ratio from which a single-channel frame is taken for a raw mosaic: a
// mono image's phases differ by well under a percent over a frame.
constexpr double kMosaicPhaseRatio = 1.25;
// A raw frame whose two green phases, where `bayer` (rig.yaml's) has them,
// differ by more than half while the other two phases agree within a
// fifth: its greens are on the other diagonal, and the patterns that have
// them there ("grbg or gbrg", "rggb or bggr"); "" if not so (and for bayer
// none). (A red/blue swap, rggb for bggr, keeps the greens: not seen here.)
std::string OtherBayerDiagonal(const cv::Mat& raw, const std::string& bayer);

// A 10-, 12- or 14-bit camera's frames saved unpacked hold their samples in
// the low bits of 16-bit pixels, 2^(16 - bits) times darker than the
// pipeline's thresholds (features, clipping) take 16-bit frames to be; the
// simulator's 12-bit frames are scaled to the full range. Scales a 16-bit
// frame's samples up to it (`sample_bits` 9-15; 0 or 16: as stored).
// Throws uwscan::Error naming `file` for a frame that is not 16-bit or a
// sample that does not fit `sample_bits`.
void ScaleLowBitSamples(cv::Mat* image, int sample_bits, const std::filesystem::path& file);
// The bits a 16-bit frame's samples seem to use when they look like a
// camera's 10 or 12 in the low bits (the brightest under 2^bits, and not
// all multiples of 4, as full-range samples of so few bits are); 0 if not.
// (A 14-bit camera's would be a quarter of full scale: too like a dark
// 16-bit frame to say.)
int LowSampleBits(const cv::Mat& image);
// The largest sample of an 8- or 16-bit image (frames are one or the
// other): 65535 for 16 bits, else 255.
double FullScale(const cv::Mat& image);
// The share of an image's samples (all channels) above 2 % of full scale.
// A frame with almost none (under kBlackFrameLitShare) is black: a lens
// cap, the lights off, an exposure far too short. A laser line alone, in
// a dark sea, lights about 0.4 % of a frame's pixels.
double LitShare(const cv::Mat& image);
constexpr double kBlackFrameLitShare = 1e-3;
// A camera frame as read, made what the pipeline takes: an alpha channel
// (PNGs exported as RGBA) dropped, low-bit samples scaled up
// (ScaleLowBitSamples). Throws uwscan::Error naming `file` for another
// number of channels than 1 or 3 (after the alpha).
void PrepareFrame(cv::Mat* image, int sample_bits, const std::filesystem::path& file);
// Throws uwscan::UsageError unless 9-16 (the commands' --sample-bits).
void CheckSampleBitsOption(int sample_bits);

// What a camera's first frame says of how it is read: a raw mosaic taken for
// a mono image, samples in the low bits read as stored, the greens off the
// rig's Bayer pattern, or a black frame.
struct FrameDoubts {
  std::filesystem::path file;       // the frame looked at (empty: none)
  std::string bayer;                // as it was read ("none": a mono camera)
  bool from_rig = true;             // bayer is rig.yaml's, not for want of a rig
  double mosaic_phase_ratio = 0.0;  // MosaicPhaseRatio, if above kMosaicPhaseRatio
  int low_sample_bits = 0;          // LowSampleBits, if read as stored
  std::string other_bayer;          // OtherBayerDiagonal
  double lit_share = 1.0;           // LitShare (not looked at: 1)
  // One line for each, naming the frame and what to set.
  std::vector<std::string> Warnings() const;
};
// `bayer` is the camera's in rig.yaml ("none" without one: `from_rig`
// false), `sample_bits` the command's --sample-bits.
FrameDoubts InspectFrame(const cv::Mat& image, const std::filesystem::path& file,
                         const std::string& bayer, bool from_rig, int sample_bits);

// The image files of a folder (png, jpg, jpeg, tif, tiff, pgm, ppm, bmp, any
// case), sorted by name. Throws uwscan::Error naming the folder if it is
// none or holds no image; for a dataset folder (images in its frames/) the
// error says where they are.
std::vector<std::filesystem::path> ListImageFiles(const std::filesystem::path& folder);

}  // namespace uwscan
