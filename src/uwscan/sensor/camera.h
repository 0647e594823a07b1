// Runtime camera: parameters plus the model that interprets them. The maths
// lives in the stateless templates of pinhole.h and flatport.h; this class
// only dispatches on the model and converts to Eigen types.
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>
#include <utility>

#include "uwscan/geometry/rigid3d.h"
#include "uwscan/sensor/flatport.h"

namespace uwscan {

enum class CameraModelId { kPinhole, kFlatPort };
enum class ProjectionMethod { kExact, kTaylor, kPinhole };

const char* CameraModelName(CameraModelId model);
std::optional<CameraModelId> CameraModelFromName(const std::string& name);
std::optional<ProjectionMethod> ProjectionMethodFromName(const std::string& name);

// Bounds of a rig's lengths, well above any real one: a value above is
// millimetres (or centimetres) given for metres.
constexpr double kMaxPortAirGapM = 0.5;
constexpr double kMaxPortGlassM = 0.2;
constexpr double kMaxRigOffsetM = 20.0;  // between cameras, lasers and the rig
// Throws uwscan::Error "WHAT is V m: rig.yaml's distances are in metres (V mm
// is ...), and NAME is under MAX m" when |value_m| > max_m.
void CheckMetres(double value_m, double max_m, const std::string& what, const std::string& name);

// Flat port geometry and media (thesis Tab. 4.4), see architecture.md.
struct FlatPort {
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // unit, camera -> water
  double d_air = 0.005;                               // camera centre to inner glass surface (m)
  double d_glass = 0.010;                             // glass thickness (m)
  double n_air = 1.0;
  double n_glass = 1.77;
  double n_water = 1.337;

  std::array<double, 5> Params() const { return {d_air, d_glass, n_air, n_glass, n_water}; }
  // Tilt of the port against the optical axis (rad).
  double TiltRad() const;
};

// A ray in the camera frame: origin (on the outer glass surface for a flat
// port, the centre for a pinhole) and unit direction in the outer medium.
struct Ray {
  Eigen::Vector3d origin;
  Eigen::Vector3d direction;
  Eigen::Vector3d At(double lambda) const { return origin + lambda * direction; }
  // The ray in frame a, given in frame b.
  Ray Transformed(const Rigid3d& a_from_b) const {
    return {a_from_b * origin, a_from_b.rotation * direction};
  }
};

struct Camera {
  std::string name = "cam0";
  int width = 1280;
  int height = 960;
  std::string bayer = "none";  // none | rggb | bggr | grbg | gbrg
  CameraModelId model = CameraModelId::kFlatPort;
  std::array<double, 4> intrinsics{785.0, 785.0, 640.0, 480.0};  // fx fy cx cy
  std::array<double, 5> distortion{0, 0, 0, 0, 0};               // k1 k2 p1 p2 k3
  FlatPort port;
  Rigid3d rig_from_camera;

  // Camera-frame point -> pixel. For a pinhole camera every method is the
  // pinhole projection; for a flat port, kPinhole ignores the port, kTaylor
  // runs `taylor_iterations` steps from the paraxial start.
  std::optional<Eigen::Vector2d> Project(const Eigen::Vector3d& point_in_camera,
                                         ProjectionMethod method = ProjectionMethod::kExact,
                                         int taylor_iterations = 2) const;
  // Two pixels the exact projection lies between, on the segment joining
  // them (up to the lens distortion's bend over that tiny segment), for a
  // flat port at most `tolerance` apart in the sine of the air ray's angle
  // (FlatPortModel::BracketAirRay); a pinhole's pixel twice. For deciding
  // which cell a point falls in at half Project's cost. None where
  // only Project can tell.
  std::optional<std::pair<Eigen::Vector2d, Eigen::Vector2d>> ProjectBounds(
      const Eigen::Vector3d& point_in_camera, double tolerance) const;
  // Pixel -> ray in the outer medium.
  std::optional<Ray> BackProject(const Eigen::Vector2d& pixel) const;

  bool IsFlatPort() const { return model == CameraModelId::kFlatPort; }
  bool InImage(const Eigen::Vector2d& pixel, double margin = 0.0) const;

  // Throws uwscan::Error prefixed with `context` when a parameter is invalid.
  void Check(const std::string& context) const;

  // The simulated cameras of thesis Tab. 4.5 (1280x960, f = 785 px).
  static Camera Flat1();
  static Camera Flat2();
  static Camera Flat3();
};

// The camera of the image resized by `factor` (0.5: half width and height):
// intrinsics scaled about pixel centres (OpenCV convention, (0, 0) is the
// centre of the first pixel), distortion and port unchanged.
Camera ScaledCamera(const Camera& camera, double factor);

// "image is 640x480 but camera 'cam0' is 1280x960", and what the sizes
// suggest: frames scaled by one factor in both directions (binned or
// resized), with the intrinsics for their size; or turned by 90 degrees.
std::string ImageSizeMismatch(const Camera& camera, int cols, int rows);

// An option giving the distance the camera looks at (m): throws
// uwscan::UsageError unless finite and in (min_m, 100] (an optical scanner
// sees some metres; 2000 is the water's depth or millimetres).
void CheckViewingDistanceOption(const std::string& option, double metres, double min_m);

}  // namespace uwscan
