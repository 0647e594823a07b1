#include "uwscan/io/dataset.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "uwscan/util/error.h"

namespace uwscan {
namespace {

namespace fs = std::filesystem;

class FramesCsvTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("uwscan_frames_csv_" + std::to_string(getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path Write(const std::string& text) {
    const fs::path path = dir_ / "frames.csv";
    std::ofstream(path) << text;
    return path;
  }
  fs::path dir_;
};

TEST_F(FramesCsvTest, RoundTripsAngleAndLaserOn) {
  const fs::path path = dir_ / "written.csv";
  {
    FramesCsvWriter writer(path, /*with_laser_angle=*/true, /*with_laser_on=*/true);
    writer.Add({0, 0.0, "frames/000000.png", 0.125, true});
    writer.Add({1, 1.0 / 144, "frames/000001.png", -0.25, false});
    writer.Commit();
  }
  const std::vector<FrameRecord> frames = ReadFramesCsv(path);
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[1].index, 1);
  EXPECT_DOUBLE_EQ(frames[1].timestamp_s, 1.0 / 144);
  EXPECT_DOUBLE_EQ(*frames[1].laser_angle_rad, -0.25);
  EXPECT_TRUE(*frames[0].laser_on);
  EXPECT_FALSE(*frames[1].laser_on);

  const auto only_on = ReadFramesCsv(Write("index,timestamp_s,file,laser_on\n0,0,a.png,0\n"));
  ASSERT_EQ(only_on.size(), 1u);
  EXPECT_FALSE(only_on[0].laser_angle_rad.has_value());
  EXPECT_FALSE(*only_on[0].laser_on);
  const auto plain = ReadFramesCsv(Write("index,timestamp_s,file\n0,0,a.png\n"));
  EXPECT_FALSE(plain[0].laser_on.has_value());  // always on
}

// A frames.csv written on Windows separates folders with '\': its frames
// are found (every one was "no such image").
TEST_F(FramesCsvTest, WindowsFolderSeparatorsAreRead) {
  const auto frames = ReadFramesCsv(Write("index,timestamp_s,file\n0,0,frames\\000000.png\n"));
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].file, "frames/000000.png");
}

// Windows editors and Excel save text with a UTF-8 byte order mark; the
// header was refused with the mark invisible in the message.
TEST_F(FramesCsvTest, AByteOrderMarkIsSkipped) {
  const auto frames = ReadFramesCsv(Write("\xEF\xBB\xBFindex,timestamp_s,file\n0,0,a.png\n"));
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].file, "a.png");
}

TEST_F(FramesCsvTest, ErrorsNameTheFileAndLine) {
  const auto message = [&](const std::string& text) {
    try {
      ReadFramesCsv(Write(text));
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("index,timestamp_s,file,laser_on,laser_angle_rad\n").find("header must be"),
            std::string::npos);
  EXPECT_NE(message("index,timestamp_s,file,laser_on\n0,0,a.png,yes\n").find("frames.csv:2"),
            std::string::npos);
  EXPECT_NE(message("index,timestamp_s,file,laser_on\n0,0,a.png,yes\n").find("laser_on must be"),
            std::string::npos);
  EXPECT_NE(message("index,timestamp_s,file,laser_on\n0,0,a.png\n").find("expected 4 fields"),
            std::string::npos);
  EXPECT_NE(message("index,timestamp_s,file\n0,0.5,a.png\n1,0.25,b.png\n")
                .find("frames.csv:3: timestamps must increase (0.25 after 0.5)"),
            std::string::npos);
  EXPECT_NE(message("index,timestamp_s,file\n0,0.5,a.png\n1,0.5,b.png\n").find("must increase"),
            std::string::npos);
  EXPECT_NE(message("index,timestamp_s,file\n7,0.5,a.png\n7,0.6,b.png\n")
                .find("frames.csv:3: frame indices must increase (7 after 7)"),
            std::string::npos);
  EXPECT_NE(message("index,timestamp_s,file\n0,nan,a.png\n").find("frames.csv:2: timestamp_s"),
            std::string::npos);
  EXPECT_NE(message("index,timestamp_s,file,laser_angle_rad\n0,0,a.png,inf\n").find("finite"),
            std::string::npos);
  EXPECT_NE(message("index,timestamp_s,file,laser_angle_rad\n0,0,a.png,0.5deg\n")
                .find("frames.csv:2: index, timestamp_s and laser_angle_rad must be numbers"),
            std::string::npos);
  // Timestamps in another unit (a 144 Hz camera's, exported in nanoseconds
  // or microseconds): refused with the unit they look like.
  EXPECT_NE(
      message("index,timestamp_s,file\n0,0,a.png\n1,6944444,b.png\n2,13888889,c.png\n")
          .find("frames.csv: timestamp_s: timestamps step by 6.94444e+06 s from one to the next "
                "(median): they are in seconds, and these look like nanoseconds (divide by 1e9)"),
      std::string::npos);
  EXPECT_NE(message("index,timestamp_s,file\n0,0,a.png\n1,6944,b.png\n")
                .find("look like microseconds (divide by 1e6)"),
            std::string::npos);
  // Epoch seconds, and a still camera's frames a minute apart, are seconds.
  EXPECT_EQ(message("index,timestamp_s,file\n0,1700000000.000,a.png\n1,1700000000.007,b.png\n"),
            "no error");
  EXPECT_EQ(message("index,timestamp_s,file\n0,0,a.png\n1,60,b.png\n"), "no error");
  // Servo angles in degrees: a sweep over 23 "radians", or one held at 45.
  EXPECT_NE(message("index,timestamp_s,file,laser_angle_rad\n0,0,a.png,5.7\n1,1,b.png,-17.2\n")
                .find("frames.csv: laser_angle_rad runs from -17.2 to 5.7, more than a half turn "
                      "of the servo or beyond a whole one: in degrees? they are radians"),
            std::string::npos);
  EXPECT_NE(message("index,timestamp_s,file,laser_angle_rad\n0,0,a.png,45\n").find("in degrees?"),
            std::string::npos);
  EXPECT_EQ(message("index,timestamp_s,file,laser_angle_rad\n0,0,a.png,0.1\n1,1,b.png,-0.3\n"),
            "no error");
}

// A 144 Hz sequence with the timestamps' jitter of a real recorder
// (+-10 % of a frame) and frames 10 and 20-22 dropped: two gaps, four
// frames, the longest four frame intervals.
TEST(FrameGapsTest, CountsTheFramesTheRecorderDropped) {
  const double dt = 1.0 / 144.0;
  std::vector<FrameRecord> all, dropped;
  for (int i = 0; i < 60; ++i) {
    FrameRecord record;
    record.index = i;
    record.timestamp_s = i * dt + 0.1 * dt * std::sin(1.7 * i);
    all.push_back(record);
    if (i != 10 && (i < 20 || i > 22)) dropped.push_back(record);
  }
  const FrameGaps none = FindFrameGaps(all);
  EXPECT_EQ(none.gaps, 0);
  EXPECT_EQ(none.missing, 0);
  const FrameGaps gaps = FindFrameGaps(dropped);
  EXPECT_EQ(gaps.gaps, 2);
  EXPECT_EQ(gaps.missing, 4);
  EXPECT_NEAR(gaps.longest_s, 4 * dt, 0.25 * dt);
  EXPECT_EQ(FindFrameGaps({}).missing, 0);
  EXPECT_EQ(FindFrameGaps(std::vector<FrameRecord>(all.begin(), all.begin() + 2)).missing, 0);
  EXPECT_NEAR(none.median_step_s, dt, 0.1 * dt);
}

// A camera's milliseconds read as seconds (a 144 Hz scan 6.9 "s" a frame)
// pass the unit check, which refuses only steps of minutes: said, with what
// to do (the scan ran tracking every frame and said "1341x real time").
TEST(FrameGapsTest, FramesSecondsApartAreDoubted) {
  std::vector<FrameRecord> frames(5);
  for (int i = 0; i < 5; ++i) frames[i].timestamp_s = i * 1000.0 / 144;
  EXPECT_EQ(SlowFramesWarning(FindFrameGaps(frames), "d/frames.csv"),
            "d/frames.csv: the frames are 6.944 s apart (median): 0.144 frames a second; if "
            "timestamp_s is in milliseconds, divide it by 1000");
  for (int i = 0; i < 5; ++i) frames[i].timestamp_s = i / 144.0;
  EXPECT_EQ(SlowFramesWarning(FindFrameGaps(frames), "d/frames.csv"), "");
  for (int i = 0; i < 5; ++i) frames[i].timestamp_s = i * 0.9;  // a slow servo scan
  EXPECT_EQ(SlowFramesWarning(FindFrameGaps(frames), "d/frames.csv"), "");
}

}  // namespace
}  // namespace uwscan
