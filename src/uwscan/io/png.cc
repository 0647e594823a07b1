#include "uwscan/io/png.h"

#include <libdeflate.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <opencv2/imgproc.hpp>

#include "uwscan/util/error.h"

namespace uwscan {
namespace {

constexpr uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};

uint32_t BigEndian32(const uint8_t* p) {
  return (uint32_t(p[0]) << 24) | (uint32_t(p[1]) << 16) | (uint32_t(p[2]) << 8) | uint32_t(p[3]);
}

struct Header {
  uint32_t width = 0, height = 0;
  int bit_depth = 0, colour_type = 0, interlace = 0;
};

struct DecompressorDeleter {
  void operator()(libdeflate_decompressor* d) const { libdeflate_free_decompressor(d); }
};

libdeflate_decompressor* ThreadDecompressor() {
  thread_local std::unique_ptr<libdeflate_decompressor, DecompressorDeleter> decompressor(
      libdeflate_alloc_decompressor());
  UWS_CHECK(decompressor != nullptr, "PNG: out of memory for the decompressor");
  return decompressor.get();
}

uint8_t Paeth(int a, int b, int c) {
  const int p = a + b - c;
  const int pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
  if (pa <= pb && pa <= pc) return uint8_t(a);
  return pb <= pc ? uint8_t(b) : uint8_t(c);
}

// Undoes one row's filter in place; `prior` is the previous unfiltered row
// (zeros for the first), `bpp` the bytes per complete pixel.
bool Unfilter(int type, uint8_t* row, const uint8_t* prior, size_t length, size_t bpp) {
  switch (type) {
    case 0:
      return true;
    case 1:
      for (size_t i = bpp; i < length; ++i) row[i] = uint8_t(row[i] + row[i - bpp]);
      return true;
    case 2:
      for (size_t i = 0; i < length; ++i) row[i] = uint8_t(row[i] + prior[i]);
      return true;
    case 3:
      for (size_t i = 0; i < bpp; ++i) row[i] = uint8_t(row[i] + (prior[i] >> 1));
      for (size_t i = bpp; i < length; ++i) {
        row[i] = uint8_t(row[i] + ((int(row[i - bpp]) + int(prior[i])) >> 1));
      }
      return true;
    case 4:
      for (size_t i = 0; i < bpp; ++i) row[i] = uint8_t(row[i] + prior[i]);
      for (size_t i = bpp; i < length; ++i) {
        row[i] = uint8_t(row[i] + Paeth(row[i - bpp], prior[i], prior[i - bpp]));
      }
      return true;
    default:
      return false;
  }
}

}  // namespace

bool HasPngSignature(const std::vector<uint8_t>& bytes) {
  return bytes.size() >= sizeof(kSignature) &&
         std::memcmp(bytes.data(), kSignature, sizeof(kSignature)) == 0;
}

std::optional<cv::Mat> DecodePng(const std::vector<uint8_t>& bytes, const std::string& name) {
  UWS_CHECK(HasPngSignature(bytes), name, ": not a PNG file");
  Header header;
  bool have_header = false, have_end = false;
  // The IDAT chunks' data, concatenated, and the inflated rows: buffers
  // kept per thread, so that a sequence of frames does not map and fault
  // in fresh megabytes for each.
  thread_local std::vector<uint8_t> stream, raw;
  stream.clear();
  size_t at = sizeof(kSignature);
  while (!have_end) {
    UWS_CHECK(bytes.size() - at >= 12, name, ": truncated PNG (no IEND chunk)");
    const uint8_t* chunk = bytes.data() + at;
    const uint32_t length = BigEndian32(chunk);
    UWS_CHECK(length <= 0x7fffffffu && bytes.size() - at - 12 >= length, name,
              ": truncated PNG (a chunk runs past the end of the file)");
    const std::string type(reinterpret_cast<const char*>(chunk + 4), 4);
    const uint8_t* data = chunk + 8;
    const uint32_t crc = libdeflate_crc32(0, chunk + 4, length + 4);
    UWS_CHECK(crc == BigEndian32(data + length), name, ": damaged PNG (CRC mismatch in chunk ",
              type, ")");
    at += 12 + size_t(length);
    if (!have_header) {
      UWS_CHECK(type == "IHDR" && length == 13, name, ": damaged PNG (IHDR is not first)");
      header.width = BigEndian32(data);
      header.height = BigEndian32(data + 4);
      header.bit_depth = data[8];
      header.colour_type = data[9];
      header.interlace = data[12];
      UWS_CHECK(header.width > 0 && header.height > 0 && header.width <= (1u << 20) &&
                    header.height <= (1u << 20),
                name, ": PNG of size ", header.width, "x", header.height, " not supported");
      UWS_CHECK(data[10] == 0 && data[11] == 0 && header.interlace <= 1, name,
                ": damaged PNG (unknown compression, filter or interlace method)");
      have_header = true;
    } else if (type == "IDAT") {
      stream.insert(stream.end(), data, data + length);
    } else if (type == "IEND") {
      have_end = true;
    } else if (type == "tRNS") {
      return std::nullopt;  // a transparent colour: OpenCV adds an alpha channel
    } else if (type != "PLTE" && (type[0] & 0x20) == 0) {
      return std::nullopt;  // another critical chunk: not ours to interpret
    }
  }
  const bool ours = (header.colour_type == 0 || header.colour_type == 2) &&
                    (header.bit_depth == 8 || header.bit_depth == 16) && header.interlace == 0;
  if (!ours) return std::nullopt;
  UWS_CHECK(!stream.empty(), name, ": damaged PNG (no image data)");

  const int channels = header.colour_type == 2 ? 3 : 1;
  const size_t sample_bytes = size_t(header.bit_depth / 8);
  const size_t bpp = size_t(channels) * sample_bytes;
  const size_t row_bytes = size_t(header.width) * bpp;
  raw.resize(size_t(header.height) * (row_bytes + 1));
  const libdeflate_result result = libdeflate_zlib_decompress(
      ThreadDecompressor(), stream.data(), stream.size(), raw.data(), raw.size(), nullptr);
  UWS_CHECK(result == LIBDEFLATE_SUCCESS, name, ": damaged PNG (",
            result == LIBDEFLATE_SHORT_OUTPUT         ? "too little image data"
            : result == LIBDEFLATE_INSUFFICIENT_SPACE ? "too much image data"
                                                      : "corrupt compressed data",
            ")");

  const int depth = header.bit_depth == 16 ? CV_16U : CV_8U;
  cv::Mat image(int(header.height), int(header.width), CV_MAKETYPE(depth, channels));
  const std::vector<uint8_t> zeros(row_bytes, 0);
  const uint8_t* prior = zeros.data();
  for (uint32_t y = 0; y < header.height; ++y) {
    uint8_t* line = raw.data() + size_t(y) * (row_bytes + 1);
    UWS_CHECK(Unfilter(line[0], line + 1, prior, row_bytes, bpp), name,
              ": damaged PNG (unknown filter type ", int(line[0]), " on row ", y, ")");
    prior = line + 1;
    uint8_t* out = image.ptr<uint8_t>(int(y));
    if (sample_bytes == 1) {
      std::memcpy(out, line + 1, row_bytes);
    } else {
      // Big-endian samples to the machine's order.
      uint16_t* out16 = reinterpret_cast<uint16_t*>(out);
      const uint8_t* in = line + 1;
      for (size_t i = 0; i < row_bytes / 2; ++i) {
        out16[i] = uint16_t((uint16_t(in[2 * i]) << 8) | in[2 * i + 1]);
      }
    }
  }
  if (channels == 3) cv::cvtColor(image, image, cv::COLOR_RGB2BGR);  // as OpenCV holds them
  return image;
}

}  // namespace uwscan
