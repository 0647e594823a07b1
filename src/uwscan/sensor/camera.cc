#include "uwscan/sensor/camera.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "uwscan/util/error.h"

namespace uwscan {

const char* CameraModelName(CameraModelId model) {
  return model == CameraModelId::kPinhole ? "pinhole" : "flatport";
}

std::optional<CameraModelId> CameraModelFromName(const std::string& name) {
  if (name == "pinhole") return CameraModelId::kPinhole;
  if (name == "flatport") return CameraModelId::kFlatPort;
  return std::nullopt;
}

std::optional<ProjectionMethod> ProjectionMethodFromName(const std::string& name) {
  if (name == "exact") return ProjectionMethod::kExact;
  if (name == "taylor") return ProjectionMethod::kTaylor;
  if (name == "pinhole") return ProjectionMethod::kPinhole;
  return std::nullopt;
}

double FlatPort::TiltRad() const {
  return std::acos(std::clamp(normal.normalized().z(), -1.0, 1.0));
}

std::optional<Eigen::Vector2d> Camera::Project(const Eigen::Vector3d& point_in_camera,
                                               ProjectionMethod method,
                                               int taylor_iterations) const {
  Eigen::Vector2d pixel;
  const double* point = point_in_camera.data();
  if (!IsFlatPort() || method == ProjectionMethod::kPinhole) {
    if (!PinholeModel::Project(intrinsics.data(), distortion.data(), point, pixel.data())) {
      return std::nullopt;
    }
    return pixel;
  }
  const auto port_params = port.Params();
  if (method == ProjectionMethod::kExact) {
    if (!FlatPortModel::ProjectExact(intrinsics.data(), distortion.data(), port.normal.data(),
                                     port_params.data(), point, pixel.data())) {
      return std::nullopt;
    }
    return pixel;
  }
  double start[2];
  if (!FlatPortModel::PinholeStart(port.normal.data(), port_params.data(), point, start) ||
      !FlatPortModel::ProjectTaylor(intrinsics.data(), distortion.data(), port.normal.data(),
                                    port_params.data(), point, start, taylor_iterations,
                                    pixel.data())) {
    return std::nullopt;
  }
  return pixel;
}

std::optional<std::pair<Eigen::Vector2d, Eigen::Vector2d>> Camera::ProjectBounds(
    const Eigen::Vector3d& point_in_camera, double tolerance) const {
  if (!IsFlatPort()) {
    const auto pixel = Project(point_in_camera);
    if (!pixel) return std::nullopt;
    return std::pair{*pixel, *pixel};
  }
  const auto port_params = port.Params();
  double air[2][3];
  if (!FlatPortModel::BracketAirRay(port.normal.data(), port_params.data(), point_in_camera.data(),
                                    tolerance, air[0], air[1])) {
    return std::nullopt;
  }
  Eigen::Vector2d pixels[2];
  for (int i = 0; i < 2; ++i) {
    if (!PinholeModel::NormalizedToImage(intrinsics.data(), distortion.data(),
                                         air[i][0] / air[i][2], air[i][1] / air[i][2],
                                         pixels[i].data())) {
      return std::nullopt;
    }
  }
  return std::pair{pixels[0], pixels[1]};
}

std::optional<Ray> Camera::BackProject(const Eigen::Vector2d& pixel) const {
  Ray ray;
  if (!IsFlatPort()) {
    ray.origin.setZero();
    if (!PinholeModel::BackProject(intrinsics.data(), distortion.data(), pixel.x(), pixel.y(),
                                   ray.direction.data())) {
      return std::nullopt;
    }
    return ray;
  }
  const auto port_params = port.Params();
  if (!FlatPortModel::BackProject(intrinsics.data(), distortion.data(), port.normal.data(),
                                  port_params.data(), pixel.x(), pixel.y(), ray.origin.data(),
                                  ray.direction.data())) {
    return std::nullopt;
  }
  return ray;
}

bool Camera::InImage(const Eigen::Vector2d& pixel, double margin) const {
  return pixel.x() >= -0.5 + margin && pixel.y() >= -0.5 + margin &&
         pixel.x() <= width - 0.5 - margin && pixel.y() <= height - 0.5 - margin;
}

void CheckMetres(double value_m, double max_m, const std::string& what, const std::string& name) {
  UWS_CHECK(std::abs(value_m) <= max_m, what, " is ", value_m,
            " m: rig.yaml's distances are in metres (", value_m, " mm is ", value_m * 1e-3,
            "), and ", name, " is under ", max_m, " m");
}

void Camera::Check(const std::string& context) const {
  UWS_CHECK(width > 0 && height > 0, context, ": width and height must be positive");
  for (double value : intrinsics)
    UWS_CHECK(std::isfinite(value), context, ": intrinsics must be finite");
  for (double value : distortion)
    UWS_CHECK(std::isfinite(value), context, ": distortion must be finite");
  UWS_CHECK(intrinsics[0] > 0 && intrinsics[1] > 0, context, ": fx and fy must be positive");
  // The principal point near the image (within one image size of it): far
  // outside, the rig is not this camera's (or cx/cy are in another unit).
  UWS_CHECK(std::abs(intrinsics[2] - 0.5 * width) <= 1.5 * width &&
                std::abs(intrinsics[3] - 0.5 * height) <= 1.5 * height,
            context, ": the principal point (cx ", intrinsics[2], ", cy ", intrinsics[3],
            ") is far outside the ", width, "x", height, " image");
  CheckMetres(rig_from_camera.translation.norm(), kMaxRigOffsetM,
              context + ": rig_from_camera's t (its length)", "a camera's offset in the rig");
  UWS_CHECK(
      bayer == "none" || bayer == "rggb" || bayer == "bggr" || bayer == "grbg" || bayer == "gbrg",
      context, ": bayer must be one of none, rggb, bggr, grbg, gbrg (got '", bayer, "')");
  if (!IsFlatPort()) return;
  UWS_CHECK(port.normal.allFinite(), context, ": port.normal must be finite");
  const double norm = port.normal.norm();
  UWS_CHECK(norm > 0, context, ": port.normal must not be zero");
  UWS_CHECK(std::abs(norm - 1.0) < 1e-6, context, ": port.normal must be a unit vector (norm ",
            norm, ")");
  UWS_CHECK(port.normal.z() > 0, context, ": port.normal must point forward (z > 0)");
  UWS_CHECK(std::isfinite(port.d_air) && port.d_air >= 0, context,
            ": port.d_air must be a non-negative distance in metres");
  UWS_CHECK(std::isfinite(port.d_glass) && port.d_glass >= 0, context,
            ": port.d_glass must be a non-negative thickness in metres");
  // Millimetres given for metres (d_air: 7) would put the port metres away.
  CheckMetres(port.d_air, kMaxPortAirGapM, context + ": port.d_air", "a flat port's air gap");
  CheckMetres(port.d_glass, kMaxPortGlassM, context + ": port.d_glass", "a port's glass");
  for (const auto& [key, value] :
       {std::pair{"n_air", port.n_air}, std::pair{"n_glass", port.n_glass},
        std::pair{"n_water", port.n_water}}) {
    UWS_CHECK(std::isfinite(value) && value >= 1.0, context, ": port.", key,
              " must be a refraction index >= 1 (got ", value, ")");
  }
}

namespace {
Camera ThesisCamera(const Eigen::Vector3d& normal, double d_air) {
  Camera camera;
  camera.port.normal = normal.normalized();
  camera.port.d_air = d_air;
  camera.port.d_glass = 0.010;
  return camera;
}
}  // namespace

Camera ScaledCamera(const Camera& camera, double factor) {
  UWS_CHECK(factor > 0.0, "ScaledCamera: factor must be positive, got ", factor);
  Camera scaled = camera;
  scaled.width = static_cast<int>(std::lround(camera.width * factor));
  scaled.height = static_cast<int>(std::lround(camera.height * factor));
  scaled.intrinsics[0] = camera.intrinsics[0] * factor;
  scaled.intrinsics[1] = camera.intrinsics[1] * factor;
  scaled.intrinsics[2] = (camera.intrinsics[2] + 0.5) * factor - 0.5;
  scaled.intrinsics[3] = (camera.intrinsics[3] + 0.5) * factor - 0.5;
  return scaled;
}

std::string ImageSizeMismatch(const Camera& camera, int cols, int rows) {
  std::ostringstream out;
  out << "image is " << cols << "x" << rows << " but camera '" << camera.name << "' is "
      << camera.width << "x" << camera.height;
  const double factor = static_cast<double>(cols) / camera.width;
  if (cols == camera.height && rows == camera.width && cols != rows) {
    out << ": the frames are turned by 90 degrees (saved upright by a viewer or an export that "
           "applied the image's orientation tag?)";
  } else if (cols > 0 && rows > 0 && cols != camera.width &&
             std::abs(factor * camera.height - rows) < 0.5) {
    const Camera scaled = ScaledCamera(camera, factor);
    out << std::setprecision(6) << ": the frames are " << factor
        << " times its size in both directions (binned or resized); calibrate the camera at "
           "this size, or give rig.yaml the intrinsics for it: width: "
        << cols << ", height: " << rows << ", fx: " << scaled.intrinsics[0]
        << ", fy: " << scaled.intrinsics[1] << ", cx: " << scaled.intrinsics[2]
        << ", cy: " << scaled.intrinsics[3] << " (distortion and port unchanged)";
  }
  return out.str();
}

void CheckViewingDistanceOption(const std::string& option, double metres, double min_m) {
  UWS_USAGE_CHECK(std::isfinite(metres) && metres > min_m, option, " must be a distance > ", min_m,
                  " m, got ", metres);
  UWS_USAGE_CHECK(metres <= 100.0, option,
                  " is the distance (m) from the camera to what it looks at, at most 100 m (an "
                  "optical scanner sees some metres), got ",
                  metres);
}

Camera Camera::Flat1() { return ThesisCamera(Eigen::Vector3d(0, 0, 1), 0.005); }
Camera Camera::Flat2() { return ThesisCamera(Eigen::Vector3d(0, 0, 1), 0.010); }
Camera Camera::Flat3() { return ThesisCamera(Eigen::Vector3d(0.02, -0.01, 1), 0.005); }

}  // namespace uwscan
