#include "uwscan/io/rig_yaml.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "uwscan/util/error.h"

namespace uwscan {
namespace {

const char* kExample = R"(format: uwscan-rig/1
cameras:
  - name: cam0
    width: 1280
    height: 960
    bayer: none
    model: flatport
    fx: 785.0
    fy: 785.0
    cx: 640.0
    cy: 480.0
    distortion: [0, 0, 0, 0, 0]
    port:
      normal: [0, 0, 1]
      d_air: 0.005
      d_glass: 0.010
      n_air: 1.0
      n_glass: 1.77
      n_water: 1.337
    rig_from_camera: {q: [1, 0, 0, 0], t: [0, 0, 0]}
lasers:
  - name: laser0
    camera_from_laser: {q: [1, 0, 0, 0], t: [0.8, 0, 0]}
    p1: 0.0
    wavelength_nm: 532
)";

// Replaces the first occurrence of `from` in the example.
std::string Edit(const std::string& from, const std::string& to) {
  std::string text = kExample;
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

std::string ErrorOf(const std::string& text) {
  try {
    ParseRigYaml(text, "test.yaml");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(RigYaml, ReadsTheArchitectureExample) {
  const Rig rig = ParseRigYaml(kExample, "example");
  ASSERT_EQ(rig.cameras.size(), 1u);
  ASSERT_EQ(rig.lasers.size(), 1u);
  EXPECT_EQ(rig.cameras[0].name, "cam0");
  EXPECT_TRUE(rig.cameras[0].IsFlatPort());
  EXPECT_DOUBLE_EQ(rig.cameras[0].port.n_glass, 1.77);
  EXPECT_DOUBLE_EQ(rig.lasers[0].camera_from_laser.translation.x(), 0.8);
  EXPECT_DOUBLE_EQ(rig.lasers[0].wavelength_nm, 532);
}

TEST(RigYaml, RoundTripIsExact) {
  Rig rig = ParseRigYaml(kExample, "example");
  rig.cameras[0] = Camera::Flat3();  // non-trivial normal
  rig.cameras[0].distortion = {0.1 / 3.0, -1e-7, 2.5e-5, 1.0 / 7.0, 0.3};
  rig.cameras[0].rig_from_camera =
      Rigid3d(Eigen::Quaterniond(0.9, 0.1, -0.2, 0.3), Eigen::Vector3d(0.1, 1.0 / 3.0, -2.0));
  rig.lasers[0].p1 = 0.0123456789012345;
  const std::string once = RigToYaml(rig);
  const Rig back = ParseRigYaml(once, "once");
  EXPECT_EQ(RigToYaml(back), once);
  EXPECT_EQ(back.cameras[0].port.normal, rig.cameras[0].port.normal);
  EXPECT_EQ(back.cameras[0].distortion, rig.cameras[0].distortion);
  EXPECT_EQ(back.cameras[0].rig_from_camera.rotation.coeffs(),
            rig.cameras[0].rig_from_camera.rotation.coeffs());

  const auto path = std::filesystem::temp_directory_path() / "uwscan_rig_roundtrip.yaml";
  WriteRigYaml(path, rig);
  EXPECT_EQ(RigToYaml(ReadRigYaml(path)), once);
  std::filesystem::remove(path);
}

TEST(RigYaml, ErrorsNameTheFileAndTheKey) {
  struct Case {
    std::string text;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {Edit("    bayer: none\n", "    bayer: none\n    colour: 3\n"),
       "unknown key 'cameras[0].colour'"},
      {Edit("      d_glass: 0.010\n", ""), "missing key 'cameras[0].port.d_glass'"},
      {Edit("fx: 785.0", "fx: .nan"), "'cameras[0].fx' must be a number"},
      {Edit("fx: 785.0", "fx: nan"), "'cameras[0].fx' must be finite"},
      {Edit("normal: [0, 0, 1]", "normal: [0, 0, 0]"), "port.normal must not be zero"},
      {Edit("normal: [0, 0, 1]", "normal: [0, 0.1, 1]"), "port.normal must be a unit vector"},
      {Edit("d_glass: 0.010", "d_glass: -0.010"), "port.d_glass must be a non-negative"},
      {Edit("n_water: 1.337", "n_water: 0.9"), "port.n_water must be a refraction index >= 1"},
      {Edit("bayer: none", "bayer: rgbg"), "bayer must be one of"},
      {Edit("model: flatport", "model: fisheye"), "'cameras[0].model' must be pinhole or flatport"},
      {Edit("format: uwscan-rig/1", "format: uwscan-rig/2"), "'format' must be uwscan-rig/1"},
      {Edit("distortion: [0, 0, 0, 0, 0]", "distortion: [0, 0, 0]"),
       "'cameras[0].distortion' must be OpenCV's k1, k2, p1, p2[, k3] (got 3 numbers)"},
      {Edit("distortion: [0, 0, 0, 0, 0]", "distortion: [0.1, 0, 0, 0, 0, 0.02, 0, 0]"),
       "'cameras[0].distortion' has 8 coefficients and the 6th is not 0: OpenCV's rational or "
       "thin-prism model"},
      {Edit("p1: 0.0", "p1: 0.0\n    power: 1"), "unknown key 'lasers[0].power'"},
      {Edit("q: [1, 0, 0, 0], t: [0.8", "q: [2, 0, 0, 0], t: [0.8"), "unit quaternion"},
      {"cameras: [", "not valid YAML"},
      {Edit("name: cam0", "name: \"\""), "cameras[0]: name must be a plain file name"},
      {Edit("name: laser0", "name: ../x"), "lasers[0]: name must be a plain file name"},
      {Edit("cx: 640.0", "cx: 640000.0"), "the principal point (cx 640000, cy 480) is far outside"},
      // Millimetres given for metres: each was taken, and the scan went wrong.
      {Edit("d_air: 0.005", "d_air: 5"),
       "cameras[0]: port.d_air is 5 m: rig.yaml's distances are in metres (5 mm is 0.005), and a "
       "flat port's air gap is under 0.5 m"},
      {Edit("d_glass: 0.010", "d_glass: 10"), "port.d_glass is 10 m"},
      {Edit("t: [0.8, 0, 0]", "t: [800, 0, 0]"),
       "lasers[0]: camera_from_laser's t (its length) is 800 m: rig.yaml's distances are in "
       "metres (800 mm is 0.8)"},
      {Edit("t: [0, 0, 0]", "t: [0, 0, 120]"), "rig_from_camera's t (its length) is 120 m"},
      // OpenCV's cv::FileStorage calibration, as its calibration sample writes it.
      {"%YAML:1.0\n---\nimage_width: 320\nimage_height: 240\ncamera_matrix: !!opencv-matrix\n"
       "   rows: 3\n   cols: 3\n   dt: d\n   data: [ 195.6, 0., 162., 0., 195.6, 121.2, 0., 0., 1. "
       "]\n",
       "an OpenCV or ROS calibration (camera_matrix), not a uwscan rig"},
  };
  for (const auto& c : cases) {
    const std::string message = ErrorOf(c.text);
    EXPECT_NE(message.find("test.yaml"), std::string::npos) << message;
    EXPECT_NE(message.find(c.expected), std::string::npos)
        << "expected '" << c.expected << "' in '" << message << "'";
  }
}

// OpenCV's and ROS's distortion lists as they write them: four numbers
// (k3 = 0), or eight with the rational model's k4-k6 at 0.
TEST(RigYaml, DistortionAsOpenCvWritesIt) {
  const auto distortion_of = [](const std::string& list) {
    return ParseRigYaml(Edit("distortion: [0, 0, 0, 0, 0]", "distortion: " + list), "test.yaml")
        .cameras[0]
        .distortion;
  };
  const std::array<double, 5> expected{-0.3, 0.1, 0.001, -0.002, 0.0};
  EXPECT_EQ(distortion_of("[-0.3, 0.1, 0.001, -0.002]"), expected);
  EXPECT_EQ(distortion_of("[-0.3, 0.1, 0.001, -0.002, 0, 0, 0, 0]"), expected);
  EXPECT_EQ(distortion_of("[-0.3, 0.1, 0.001, -0.002, 0.05]")[4], 0.05);
}

TEST(RigYaml, MissingFileIsAnError) { EXPECT_THROW(ReadRigYaml("/nonexistent/rig.yaml"), Error); }

}  // namespace
}  // namespace uwscan
