#include "uwscan/sensor/rig.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "uwscan/util/error.h"

namespace uwscan {
namespace {

Rig TwoPods() {
  Rig rig;
  Camera left = Camera::Flat1(), right = Camera::Flat1();
  left.name = "cam0";
  right.name = "cam1";
  right.rig_from_camera =
      Rigid3d(Eigen::Quaterniond(Eigen::AngleAxisd(0.1, Eigen::Vector3d(0.2, 1, 0.1).normalized())),
              Eigen::Vector3d(0.8, 0.1, 0.02));
  rig.cameras = {left, right};
  LineProjector a, b;
  a.name = "laser0";
  a.camera_from_laser = Rigid3d(
      Eigen::Quaterniond(Eigen::AngleAxisd(1.5, Eigen::Vector3d(0.1, -0.1, 1).normalized())),
      Eigen::Vector3d(0.79, 0.0, 0.01));
  b.name = "laser1";
  b.camera_from_laser = Rigid3d(
      Eigen::Quaterniond(Eigen::AngleAxisd(-1.5, Eigen::Vector3d(0.1, 0.1, 1).normalized())),
      Eigen::Vector3d(0.0, 0.1, 0.01));
  b.p1 = 0.01;
  rig.lasers = {a, b};
  return rig;
}

double PoseDistance(const Rigid3d& a, const Rigid3d& b) {
  return (a.translation - b.translation).norm() + a.rotation.angularDistance(b.rotation);
}

TEST(Rig, ReorderedKeepsEveryCameraLaserPair) {
  const Rig rig = TwoPods();
  const Rig seen_from_right = rig.Reordered(1, 1);
  ASSERT_EQ(seen_from_right.cameras.size(), 2u);
  ASSERT_EQ(seen_from_right.lasers.size(), 2u);
  EXPECT_EQ(seen_from_right.cameras[0].name, "cam1");
  EXPECT_EQ(seen_from_right.lasers[0].name, "laser1");
  EXPECT_EQ(seen_from_right.CameraByName("").name, "cam1");
  EXPECT_DOUBLE_EQ(seen_from_right.lasers[0].p1, 0.01);
  // The same physical geometry, whichever camera comes first.
  for (size_t c = 0; c < 2; ++c) {
    for (size_t l = 0; l < 2; ++l) {
      EXPECT_LT(
          PoseDistance(seen_from_right.CameraFromLaser(1 - c, 1 - l), rig.CameraFromLaser(c, l)),
          1e-12)
          << c << " " << l;
    }
  }
  EXPECT_LT(PoseDistance(rig.CameraFromCamera(0, 1), rig.cameras[1].rig_from_camera), 1e-12);
  EXPECT_LT(PoseDistance(rig.CameraFromCamera(1, 0) * rig.CameraFromCamera(0, 1), Rigid3d()),
            1e-12);
  // First camera and laser unchanged: the same rig.
  const Rig same = rig.Reordered(0, 0);
  EXPECT_LT(PoseDistance(same.lasers[1].camera_from_laser, rig.lasers[1].camera_from_laser), 1e-12);
  EXPECT_THROW(rig.Reordered(2, 0), Error);
}

TEST(Camera, ImageSizeMismatchSaysWhatTheSizesSuggest) {
  const Camera camera = Camera::Flat1();  // 1280x960, f 785, centre (640, 480)
  // Binned 2x2: the centre of pixel (640, 480) lies at (319.75, 239.75) of
  // the half-size image, whose pixels are twice as large.
  EXPECT_EQ(ImageSizeMismatch(camera, 640, 480),
            "image is 640x480 but camera 'cam0' is 1280x960: the frames are 0.5 times its size in "
            "both directions (binned or resized); calibrate the camera at this size, or give "
            "rig.yaml the intrinsics for it: width: 640, height: 480, fx: 392.5, fy: 392.5, cx: "
            "319.75, cy: 239.75 (distortion and port unchanged)");
  EXPECT_NE(ImageSizeMismatch(camera, 1920, 1440).find("1.5 times its size"), std::string::npos);
  EXPECT_NE(ImageSizeMismatch(camera, 960, 1280).find("turned by 90 degrees"), std::string::npos);
  // A crop (another aspect) suggests nothing.
  EXPECT_EQ(ImageSizeMismatch(camera, 1280, 720),
            "image is 1280x720 but camera 'cam0' is 1280x960");
  EXPECT_EQ(ImageSizeMismatch(camera, 0, 0), "image is 0x0 but camera 'cam0' is 1280x960");
}

}  // namespace
}  // namespace uwscan
