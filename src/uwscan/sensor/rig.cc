#include "uwscan/sensor/rig.h"

#include <cmath>
#include <set>

#include "uwscan/sensor/line_projector.h"
#include "uwscan/util/error.h"

namespace uwscan {
namespace {
std::array<double, 4> QuaternionWxyz(const Eigen::Quaterniond& q) {
  return {q.w(), q.x(), q.y(), q.z()};
}
}  // namespace

std::optional<Eigen::Vector3d> LineProjector::Triangulate(const Ray& ray) const {
  const auto q = QuaternionWxyz(camera_from_laser.rotation);
  Eigen::Vector3d point;
  if (!LineProjectorModel::Triangulate(q.data(), camera_from_laser.translation.data(), p1,
                                       ray.origin.data(), ray.direction.data(), point.data())) {
    return std::nullopt;
  }
  return point;
}

double LineProjector::SineToSheet(const Eigen::Vector3d& direction,
                                  const Eigen::Vector3d& point_in_camera) const {
  const Eigen::Matrix3d laser_from_camera =
      camera_from_laser.rotation.toRotationMatrix().transpose();
  const Eigen::Vector3d p = laser_from_camera * (point_in_camera - camera_from_laser.translation);
  const Eigen::Vector3d d = laser_from_camera * direction;
  // The sheet y z = p1 x^2 (eq. 4.30 times z^2); its normal is the gradient.
  const Eigen::Vector3d normal(-2.0 * p1 * p.x(), p.z(), p.y());
  const double norms = normal.norm() * d.norm();
  return norms > 0.0 ? std::abs(normal.dot(d)) / norms : 0.0;
}

std::optional<double> LineProjector::SheetResidual(const Eigen::Vector3d& point_in_camera) const {
  const auto q = QuaternionWxyz(camera_from_laser.rotation);
  double residual;
  if (!LineProjectorModel::SheetResidual(q.data(), camera_from_laser.translation.data(), p1,
                                         point_in_camera.data(), &residual)) {
    return std::nullopt;
  }
  return residual;
}

void LineProjector::Check(const std::string& context) const {
  UWS_CHECK(std::isfinite(p1), context, ": p1 must be finite");
  UWS_CHECK(std::isfinite(wavelength_nm) && wavelength_nm >= 300 && wavelength_nm <= 1100, context,
            ": wavelength_nm must be between 300 and 1100 (got ", wavelength_nm, ")");
  UWS_CHECK(
      camera_from_laser.translation.allFinite() && camera_from_laser.rotation.coeffs().allFinite(),
      context, ": camera_from_laser must be finite");
  CheckMetres(camera_from_laser.translation.norm(), kMaxRigOffsetM,
              context + ": camera_from_laser's t (its length)", "a laser's offset from the camera");
}

namespace {
// "FILE: " for a rig read from a file.
std::string Named(const std::string& source) { return source.empty() ? "" : source + ": "; }
}  // namespace

const Camera& Rig::CameraByName(const std::string& name) const {
  UWS_CHECK(!cameras.empty(), Named(source), "the rig has no camera");
  if (name.empty()) return cameras.front();
  for (const auto& camera : cameras) {
    if (camera.name == name) return camera;
  }
  UWS_THROW(Named(source), "the rig has no camera named '", name, "'");
}

const LineProjector& Rig::LaserByName(const std::string& name) const {
  UWS_CHECK(!lasers.empty(), Named(source), "the rig has no laser");
  if (name.empty()) return lasers.front();
  for (const auto& laser : lasers) {
    if (laser.name == name) return laser;
  }
  UWS_THROW(Named(source), "the rig has no laser named '", name, "'");
}

Rigid3d Rig::CameraFromLaser(size_t camera_index, size_t laser_index) const {
  UWS_CHECK(camera_index < cameras.size() && laser_index < lasers.size(), "rig index out of range");
  return CameraFromCamera(camera_index, 0) * lasers[laser_index].camera_from_laser;
}

Rigid3d Rig::CameraFromCamera(size_t to_index, size_t from_index) const {
  UWS_CHECK(to_index < cameras.size() && from_index < cameras.size(), "rig index out of range");
  return cameras[to_index].rig_from_camera.Inverse() * cameras[from_index].rig_from_camera;
}

Rig Rig::Reordered(size_t first_camera, size_t first_laser) const {
  UWS_CHECK(first_camera < cameras.size() && first_laser < lasers.size(), "rig index out of range");
  Rig rig;
  rig.source = source;
  const auto first_then_others = [](size_t first, size_t count) {
    std::vector<size_t> order = {first};
    for (size_t i = 0; i < count; ++i) {
      if (i != first) order.push_back(i);
    }
    return order;
  };
  for (size_t c : first_then_others(first_camera, cameras.size()))
    rig.cameras.push_back(cameras[c]);
  for (size_t l : first_then_others(first_laser, lasers.size())) {
    LineProjector laser = lasers[l];
    laser.camera_from_laser = CameraFromLaser(first_camera, l);
    rig.lasers.push_back(laser);
  }
  return rig;
}

void Rig::Check(const std::string& context) const {
  UWS_CHECK(!cameras.empty(), context, ": cameras: at least one camera is required");
  // A further camera's images are in DATASET/NAME/: a name is a plain file name.
  const auto check_name = [&](const std::string& name, const std::string& where) {
    UWS_CHECK(!name.empty() && name != "." && name != ".." &&
                  name.find_first_of("/\\") == std::string::npos,
              context, ": ", where, ": name must be a plain file name (not empty, no '/'), got '",
              name, "'");
  };
  std::set<std::string> names;
  for (size_t i = 0; i < cameras.size(); ++i) {
    cameras[i].Check(context + ": cameras[" + std::to_string(i) + "]");
    check_name(cameras[i].name, "cameras[" + std::to_string(i) + "]");
    UWS_CHECK(names.insert(cameras[i].name).second, context, ": duplicate camera name '",
              cameras[i].name, "'");
  }
  for (size_t i = 0; i < lasers.size(); ++i) {
    lasers[i].Check(context + ": lasers[" + std::to_string(i) + "]");
    check_name(lasers[i].name, "lasers[" + std::to_string(i) + "]");
    UWS_CHECK(names.insert(lasers[i].name).second, context, ": duplicate name '", lasers[i].name,
              "'");
  }
}

}  // namespace uwscan
