// A fast reader for the PNG files uwscan's datasets hold: non-interlaced
// grey or RGB, 8 or 16 bits per sample. The compressed stream is inflated
// in one call of libdeflate (about 3x faster than zlib's streaming inflate
// on the simulator's 1280x960 frames) and the rows are unfiltered here;
// every chunk's CRC and the stream's Adler-32 are checked. Other kinds of
// PNG (palette, alpha, interlaced) are left to OpenCV.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

namespace uwscan {

// True if `bytes` start with the PNG signature.
bool HasPngSignature(const std::vector<uint8_t>& bytes);

// Decodes a PNG held in memory. Returns the image as cv::imread with
// IMREAD_UNCHANGED would (CV_8U or CV_16U, 1 channel or B G R), or nullopt
// for a valid PNG of a kind this reader leaves to OpenCV. Throws
// uwscan::Error starting with `name` for a damaged file (truncated, CRC or
// checksum mismatch, bad header, wrong amount of data).
std::optional<cv::Mat> DecodePng(const std::vector<uint8_t>& bytes, const std::string& name);

}  // namespace uwscan
