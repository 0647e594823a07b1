#include "uwscan/io/png.h"

#include <gtest/gtest.h>
#include <libdeflate.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

#include "uwscan/io/image.h"
#include "uwscan/util/error.h"

namespace uwscan {
namespace {

namespace fs = std::filesystem;

void Put32(std::vector<uint8_t>* out, uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) out->push_back(uint8_t(v >> shift));
}

void PutChunk(std::vector<uint8_t>* out, const std::string& type,
              const std::vector<uint8_t>& data) {
  Put32(out, uint32_t(data.size()));
  std::vector<uint8_t> body(type.begin(), type.end());
  body.insert(body.end(), data.begin(), data.end());
  out->insert(out->end(), body.begin(), body.end());
  Put32(out, libdeflate_crc32(0, body.data(), body.size()));
}

// The bytes of one image row as PNG stores them: R G B order, big-endian.
std::vector<uint8_t> RowBytes(const cv::Mat& image, int y) {
  std::vector<uint8_t> row;
  const int channels = image.channels();
  for (int x = 0; x < image.cols; ++x) {
    for (int c = 0; c < channels; ++c) {
      const int k = channels == 3 ? 2 - c : c;
      if (image.depth() == CV_8U) {
        row.push_back(image.ptr<uint8_t>(y)[x * channels + k]);
      } else {
        const uint16_t v = image.ptr<uint16_t>(y)[x * channels + k];
        row.push_back(uint8_t(v >> 8));
        row.push_back(uint8_t(v & 0xff));
      }
    }
  }
  return row;
}

int PaethPredictor(int a, int b, int c) {
  const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
  return pa <= pb && pa <= pc ? a : (pb <= pc ? b : c);
}

// An independent PNG writer: every row filtered with `filter` (0-4, or -1
// to cycle through all five), the stream split into IDAT chunks of 1000 bytes.
std::vector<uint8_t> EncodePng(const cv::Mat& image, int filter) {
  const size_t bpp = image.elemSize();
  std::vector<uint8_t> raw, prior(image.cols * bpp, 0);
  for (int y = 0; y < image.rows; ++y) {
    const std::vector<uint8_t> row = RowBytes(image, y);
    const int type = filter >= 0 ? filter : y % 5;
    raw.push_back(uint8_t(type));
    for (size_t i = 0; i < row.size(); ++i) {
      const int a = i >= bpp ? row[i - bpp] : 0, b = prior[i], c = i >= bpp ? prior[i - bpp] : 0;
      const int predictor = type == 0   ? 0
                            : type == 1 ? a
                            : type == 2 ? b
                            : type == 3 ? (a + b) / 2
                                        : PaethPredictor(a, b, c);
      raw.push_back(uint8_t(row[i] - predictor));
    }
    prior = row;
  }
  libdeflate_compressor* compressor = libdeflate_alloc_compressor(6);
  std::vector<uint8_t> stream(libdeflate_zlib_compress_bound(compressor, raw.size()));
  stream.resize(
      libdeflate_zlib_compress(compressor, raw.data(), raw.size(), stream.data(), stream.size()));
  libdeflate_free_compressor(compressor);

  std::vector<uint8_t> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  std::vector<uint8_t> header;
  Put32(&header, uint32_t(image.cols));
  Put32(&header, uint32_t(image.rows));
  header.push_back(image.depth() == CV_16U ? 16 : 8);
  header.push_back(image.channels() == 3 ? 2 : 0);
  header.insert(header.end(), {0, 0, 0});
  PutChunk(&png, "IHDR", header);
  PutChunk(&png, "tEXt", {'a', 0, 'b'});  // ancillary: skipped
  for (size_t at = 0; at < stream.size(); at += 1000) {
    const size_t end = std::min(stream.size(), at + 1000);
    PutChunk(&png, "IDAT", std::vector<uint8_t>(stream.begin() + at, stream.begin() + end));
  }
  PutChunk(&png, "IEND", {});
  return png;
}

cv::Mat RandomImage(int type, uint32_t seed) {
  cv::Mat image(37, 53, type);
  cv::RNG rng(seed);
  rng.fill(image, cv::RNG::UNIFORM, 0, image.depth() == CV_16U ? 65536 : 256);
  // and some smooth rows, as in real images
  for (int x = 0; x < image.cols * image.channels(); ++x) {
    if (image.depth() == CV_8U)
      image.ptr<uint8_t>(5)[x] = uint8_t(x);
    else
      image.ptr<uint16_t>(5)[x] = uint16_t(x * 1000);
  }
  return image;
}

bool Equal(const cv::Mat& a, const cv::Mat& b) {
  return a.type() == b.type() && a.size() == b.size() && cv::norm(a, b, cv::NORM_INF) == 0;
}

TEST(Png, EveryFilterDepthAndColourDecodesAsWrittenAndAsOpenCVReadsIt) {
  uint32_t seed = 1;
  for (int type : {CV_8UC1, CV_16UC1, CV_8UC3, CV_16UC3}) {
    for (int filter = -1; filter <= 4; ++filter) {
      SCOPED_TRACE(testing::Message() << "type " << type << " filter " << filter);
      const cv::Mat image = RandomImage(type, seed++);
      const std::vector<uint8_t> png = EncodePng(image, filter);
      const std::optional<cv::Mat> decoded = DecodePng(png, "test.png");
      ASSERT_TRUE(decoded.has_value());
      EXPECT_TRUE(Equal(*decoded, image));
      EXPECT_TRUE(Equal(cv::imdecode(png, cv::IMREAD_UNCHANGED), image));  // libpng agrees
    }
  }
}

TEST(Png, OpenCVsOwnPngsDecodeUnchanged) {
  for (int type : {CV_8UC1, CV_16UC1, CV_8UC3, CV_16UC3}) {
    for (int level : {0, 3, 9}) {
      const cv::Mat image = RandomImage(type, uint32_t(100 + type + level));
      std::vector<uint8_t> png;
      ASSERT_TRUE(cv::imencode(".png", image, png, {cv::IMWRITE_PNG_COMPRESSION, level}));
      const std::optional<cv::Mat> decoded = DecodePng(png, "cv.png");
      ASSERT_TRUE(decoded.has_value());
      EXPECT_TRUE(Equal(*decoded, image)) << "type " << type << " level " << level;
    }
  }
}

void ExpectError(const std::vector<uint8_t>& png, const std::string& fragment) {
  try {
    DecodePng(png, "bad.png");
    ADD_FAILURE() << "no error, expected one with '" << fragment << "'";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("bad.png"), std::string::npos) << what;
    EXPECT_NE(what.find(fragment), std::string::npos) << what;
  }
}

TEST(Png, DamagedFilesGiveErrorsNamingTheFileAndTheProblem) {
  const std::vector<uint8_t> good = EncodePng(RandomImage(CV_8UC1, 7), 4);
  ExpectError(std::vector<uint8_t>(good.begin(), good.begin() + good.size() / 2), "truncated");
  ExpectError(std::vector<uint8_t>(good.begin(), good.end() - 12), "no IEND");

  std::vector<uint8_t> flipped = good;
  const std::string idat = "IDAT";
  const auto chunk = std::search(good.begin(), good.end(), idat.begin(), idat.end());
  ASSERT_NE(chunk, good.end());
  flipped[size_t(chunk - good.begin()) + 4 + 10] ^= 0x10;  // a byte of the chunk's data
  ExpectError(flipped, "CRC mismatch in chunk IDAT");

  // A consistent file whose header promises more rows than the data holds.
  cv::Mat image = RandomImage(CV_8UC1, 8);
  std::vector<uint8_t> taller = EncodePng(image, 0);
  taller[8 + 8 + 7] += 1;  // height's low byte
  const uint32_t crc = libdeflate_crc32(0, taller.data() + 12, 17);
  for (int i = 0; i < 4; ++i) taller[8 + 8 + 13 + i] = uint8_t(crc >> (24 - 8 * i));
  ExpectError(taller, "too little image data");

  // Bad filter type byte on the first row (data recompressed, CRCs right).
  cv::Mat one(4, 4, CV_8UC1, cv::Scalar(9));
  const std::vector<uint8_t> reference = EncodePng(one, 0);
  std::vector<uint8_t> raw;
  for (int y = 0; y < 4; ++y) {
    raw.push_back(7);  // the filter type byte
    for (int x = 0; x < 4; ++x) raw.push_back(9);
  }
  libdeflate_compressor* compressor = libdeflate_alloc_compressor(1);
  std::vector<uint8_t> stream(libdeflate_zlib_compress_bound(compressor, raw.size()));
  stream.resize(
      libdeflate_zlib_compress(compressor, raw.data(), raw.size(), stream.data(), stream.size()));
  libdeflate_free_compressor(compressor);
  std::vector<uint8_t> png(reference.begin(), reference.begin() + 8 + 25);  // signature, IHDR
  PutChunk(&png, "IDAT", stream);
  PutChunk(&png, "IEND", {});
  ExpectError(png, "unknown filter type 7");

  ExpectError({'G', 'I', 'F', '8'}, "not a PNG");
}

class ReadImageTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("uwscan_png_" + std::to_string(getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path Write(const std::string& name, const std::vector<uint8_t>& bytes) {
    const fs::path path = dir_ / name;
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    return path;
  }
  fs::path dir_;
};

TEST_F(ReadImageTest, OtherKindsOfImageAreLeftToOpenCV) {
  // BGRA (alpha) PNG, and a JPEG: read by OpenCV as before.
  cv::Mat bgra(20, 30, CV_8UC4, cv::Scalar(10, 20, 30, 40));
  std::vector<uint8_t> png;
  ASSERT_TRUE(cv::imencode(".png", bgra, png));
  EXPECT_FALSE(DecodePng(png, "alpha.png").has_value());
  EXPECT_TRUE(Equal(ReadImage(Write("alpha.png", png)), bgra));

  std::vector<uint8_t> jpeg;
  ASSERT_TRUE(cv::imencode(".jpg", cv::Mat(16, 16, CV_8UC1, cv::Scalar(128)), jpeg));
  const cv::Mat read = ReadImage(Write("grey.jpg", jpeg));
  EXPECT_EQ(read.type(), CV_8UC1);
  EXPECT_EQ(read.size(), cv::Size(16, 16));
}

TEST_F(ReadImageTest, WritePngAndReadImageRoundTrip) {
  for (int type : {CV_8UC1, CV_16UC1, CV_8UC3, CV_16UC3}) {
    const cv::Mat image = RandomImage(type, uint32_t(200 + type));
    const fs::path path = dir_ / ("round" + std::to_string(type) + ".png");
    WritePng(path, image);
    EXPECT_TRUE(Equal(ReadImage(path), image)) << "type " << type;
  }
}

TEST_F(ReadImageTest, UnreadableFilesAreNamed) {
  for (const auto& [name, bytes] : std::vector<std::pair<std::string, std::vector<uint8_t>>>{
           {"empty.png", {}}, {"text.png", {'h', 'e', 'l', 'l', 'o'}}}) {
    const fs::path path = Write(name, bytes);
    try {
      ReadImage(path);
      ADD_FAILURE() << name << ": no error";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(ReadImage(dir_ / "missing.png"), Error);
}

// A folder's images by name, whatever the case of their extension; other
// files, subfolders and hidden files left out (macOS writes "._NAME.png"
// beside each image it copies to a USB disk; they were read as frames, and
// every frame after them was numbered one too high); a folder without
// images, or none, is an error naming it, and a dataset folder's error says
// where its images are.
TEST_F(ReadImageTest, ListImageFilesFindsAFoldersImagesAndSaysWhereADatasetsAre) {
  const fs::path folder = dir_ / "list";
  fs::create_directories(folder / "sub.png");  // a folder, not an image
  for (const char* name :
       {"b.PNG", "a.jpg", "c.pgm", "d.tiff", "notes.txt", "e.bmp", "._a.jpg", ".hidden.png"})
    std::ofstream(folder / name) << "x";
  const std::vector<fs::path> images = ListImageFiles(folder);
  std::vector<std::string> names;
  for (const auto& path : images) names.push_back(path.filename().string());
  EXPECT_EQ(names, (std::vector<std::string>{"a.jpg", "b.PNG", "c.pgm", "d.tiff", "e.bmp"}));

  const auto message = [](const fs::path& path) {
    try {
      ListImageFiles(path);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message(dir_ / "none"), (dir_ / "none").string() + ": not a folder");
  const fs::path dataset = dir_ / "dataset";
  fs::create_directories(dataset / "frames");
  EXPECT_EQ(message(dataset),
            dataset.string() + ": no images (png, jpg, tif, pgm, ppm, bmp) in the folder");
  std::ofstream(dataset / "frames" / "000000.png") << "x";
  EXPECT_EQ(message(dataset), dataset.string() +
                                  ": no images (png, jpg, tif, pgm, ppm, bmp) in the folder; it "
                                  "is a dataset, whose images are in " +
                                  (dataset / "frames").string());
}

TEST(ImageTypeName, SaysChannelsAndBits) {
  EXPECT_EQ(ImageTypeName(CV_8UC1), "1-channel 8-bit");
  EXPECT_EQ(ImageTypeName(CV_16UC3), "3-channel 16-bit");
  EXPECT_EQ(ImageTypeName(CV_32FC1), "1-channel 32-bit float");
}

// A mono camera's frame has the same mean on its four 2x2 pixel phases; a
// raw Bayer mosaic's phases are different colours. Here a smooth texture,
// and the same texture seen through an RGGB filter under a reddish light.
TEST(MosaicPhaseRatio, TellsARawMosaicFromAMonoImage) {
  cv::Mat noise(240, 321, CV_32F);  // an odd width: the last column's phase has fewer pixels
  cv::randu(noise, 0.0, 1.0);
  cv::Mat texture;
  cv::GaussianBlur(noise, texture, cv::Size(0, 0), 3.0);
  cv::normalize(texture, texture, 40, 200, cv::NORM_MINMAX);
  cv::Mat mono, mosaic = texture.clone();
  texture.convertTo(mono, CV_8U);
  const float colour[2][2] = {{1.0f, 0.6f}, {0.6f, 0.3f}};  // R G / G B
  for (int y = 0; y < mosaic.rows; ++y)
    for (int x = 0; x < mosaic.cols; ++x) mosaic.at<float>(y, x) *= colour[y % 2][x % 2];
  cv::Mat raw, raw16, mono16;
  mosaic.convertTo(raw, CV_8U);
  mosaic.convertTo(raw16, CV_16U, 256.0);
  mono.convertTo(mono16, CV_16U, 256.0);
  EXPECT_LT(MosaicPhaseRatio(mono), 1.02);
  EXPECT_LT(MosaicPhaseRatio(mono16), 1.02);
  EXPECT_NEAR(MosaicPhaseRatio(raw), 1.0 / 0.3, 0.05);
  EXPECT_NEAR(MosaicPhaseRatio(raw16), 1.0 / 0.3, 0.05);
  EXPECT_GT(MosaicPhaseRatio(raw), kMosaicPhaseRatio);
  EXPECT_LT(MosaicPhaseRatio(mono), kMosaicPhaseRatio);
  // The rig's pattern against the frame's greens: an RGGB mosaic read as
  // GRBG or GBRG has its "greens" on red and blue; BGGR (red and blue
  // swapped) keeps them, and so does a mono image (nothing to tell).
  EXPECT_EQ(OtherBayerDiagonal(raw, "rggb"), "");
  EXPECT_EQ(OtherBayerDiagonal(raw, "bggr"), "");
  EXPECT_EQ(OtherBayerDiagonal(raw, "grbg"), "rggb or bggr");
  EXPECT_EQ(OtherBayerDiagonal(raw, "gbrg"), "rggb or bggr");
  EXPECT_EQ(OtherBayerDiagonal(raw(cv::Rect(1, 0, 320, 240)), "rggb"), "grbg or gbrg");
  EXPECT_EQ(OtherBayerDiagonal(raw, "none"), "");
  EXPECT_EQ(OtherBayerDiagonal(mono, "grbg"), "");
  // Not to be judged: colour, too small, too dark.
  cv::Mat bgr;
  cv::cvtColor(mono, bgr, cv::COLOR_GRAY2BGR);
  EXPECT_TRUE(std::isnan(MosaicPhaseRatio(bgr)));
  EXPECT_TRUE(std::isnan(MosaicPhaseRatio(raw(cv::Rect(0, 0, 8, 8)))));
  EXPECT_TRUE(std::isnan(MosaicPhaseRatio(cv::Mat(64, 64, CV_8U, cv::Scalar(3)))));
}

// A 12-bit camera's frame saved unpacked (its samples in the low bits of a
// 16-bit PNG) is told from full-range frames, and scaled up to the range
// the simulator's 12-bit frames have.
TEST(LowSampleBits, TwelveBitSamplesInTheLowBitsAreFoundAndScaledUp) {
  cv::Mat noise(60, 80, CV_32F);
  cv::randu(noise, 0.0, 1.0);
  cv::Mat low;
  noise.convertTo(low, CV_16U, 4000.0);  // 0..4000: 12 bits
  const cv::Mat full = low * 16;         // as the simulator writes 12 bits
  EXPECT_EQ(LowSampleBits(low), 12);
  EXPECT_EQ(LowSampleBits(low / 4), 10);
  EXPECT_EQ(LowSampleBits(full), 0);
  EXPECT_EQ(LowSampleBits(cv::Mat(low * 4)), 0);  // multiples of 4: full-range samples
  cv::Mat low8;
  low.convertTo(low8, CV_8U, 1.0 / 16);
  EXPECT_EQ(LowSampleBits(low8), 0);
  EXPECT_EQ(LowSampleBits(cv::Mat::zeros(8, 8, CV_16U)), 0);

  cv::Mat scaled = low.clone();
  ScaleLowBitSamples(&scaled, 12, "f.png");
  EXPECT_EQ(cv::norm(scaled, full, cv::NORM_INF), 0.0);
  cv::Mat as_stored = low.clone();
  ScaleLowBitSamples(&as_stored, 16, "f.png");
  EXPECT_EQ(cv::norm(as_stored, low, cv::NORM_INF), 0.0);
  cv::Mat too_wide = low.clone();
  too_wide.at<uint16_t>(3, 4) = 4096;
  EXPECT_THROW(
      {
        try {
          ScaleLowBitSamples(&too_wide, 12, "dir/f.png");
        } catch (const Error& e) {
          EXPECT_STREQ(e.what(), "dir/f.png: a sample of 4096 does not fit 12 bits (at most 4095)");
          throw;
        }
      },
      Error);
  EXPECT_THROW(ScaleLowBitSamples(&low8, 12, "f.png"), Error);  // not 16-bit
  EXPECT_THROW(CheckSampleBitsOption(8), UsageError);
  EXPECT_THROW(CheckSampleBitsOption(17), UsageError);
  EXPECT_NO_THROW(CheckSampleBitsOption(16));
}

// Frames exported as RGBA PNGs lose their alpha channel; other channel
// counts are refused by file.
// A black first frame (a lens cap, the lights off) is said, naming it; the
// scan used to end with "no laser line in 100 % of the frames" or "the
// odometry never started". A laser line alone in the dark is not black.
TEST(LitShare, ABlackFrameIsSaidAndALaserLineInTheDarkIsNot) {
  const auto black_warning = [](const cv::Mat& image) {
    const FrameDoubts doubts = InspectFrame(image, "f/000000.png", "none", true, 16);
    for (const std::string& warning : doubts.Warnings()) {
      if (warning.rfind("f/000000.png: a black frame: ", 0) == 0) return true;
    }
    return false;
  };
  cv::Mat dark(240, 320, CV_8UC1, cv::Scalar(3));  // 1.2 % of full scale
  EXPECT_DOUBLE_EQ(LitShare(dark), 0.0);
  EXPECT_TRUE(black_warning(dark));
  cv::Mat line = dark.clone();
  line.colRange(150, 152).setTo(200);  // 0.6 % of the pixels
  EXPECT_NEAR(LitShare(line), 2.0 / 320, 1e-12);
  EXPECT_FALSE(black_warning(line));
  // 16-bit: the same 2 % of 65535.
  EXPECT_TRUE(black_warning(cv::Mat(240, 320, CV_16UC1, cv::Scalar(1000))));
  EXPECT_FALSE(black_warning(cv::Mat(240, 320, CV_16UC1, cv::Scalar(2000))));
  // Samples in a 16-bit frame's low bits are dark for a reason said apart.
  cv::Mat low(240, 320, CV_16UC1, cv::Scalar(1001));
  const FrameDoubts doubts = InspectFrame(low, "f/000000.png", "none", true, 16);
  EXPECT_EQ(doubts.low_sample_bits, 10);
  EXPECT_FALSE(black_warning(low));
}

TEST(PrepareFrame, DropsAnAlphaChannelAndNamesOtherLayouts) {
  cv::Mat bgr(8, 10, CV_8UC3, cv::Scalar(10, 20, 30)), bgra;
  cv::cvtColor(bgr, bgra, cv::COLOR_BGR2BGRA);
  PrepareFrame(&bgra, 16, "f.png");
  ASSERT_EQ(bgra.type(), CV_8UC3);
  EXPECT_EQ(cv::norm(bgra, bgr, cv::NORM_INF), 0.0);
  cv::Mat two(8, 10, CV_8UC2, cv::Scalar(1, 2));
  try {
    PrepareFrame(&two, 16, "dir/f.png");
    ADD_FAILURE() << "a 2-channel frame was taken";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("dir/f.png: a 2-channel 8-bit image: frames are", 0), 0u)
        << e.what();
  }
}

}  // namespace
}  // namespace uwscan
