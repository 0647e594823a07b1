#include "uwscan/sim/scene.h"

#include <cmath>
#include <set>

#include "uwscan/util/error.h"

namespace uwscan::sim {
namespace {

bool InRectangle(const Eigen::Vector3d& p, double size_x, double size_y) {
  return std::abs(p.x()) <= 0.5 * size_x && std::abs(p.y()) <= 0.5 * size_y;
}

// Smallest root of a l^2 + b l + c = 0 in (lo, hi) that passes `accept`.
template <typename Accept>
std::optional<double> QuadraticRoot(double a, double b, double c, double lo, double hi,
                                    Accept accept) {
  double roots[2];
  int count = 0;
  if (std::abs(a) < 1e-14) {
    if (std::abs(b) < 1e-300) return std::nullopt;
    roots[count++] = -c / b;
  } else {
    const double disc = b * b - 4 * a * c;
    if (disc < 0) return std::nullopt;
    const double sq = std::sqrt(disc);
    const double q = b >= 0 ? -0.5 * (b + sq) : -0.5 * (b - sq);
    roots[count++] = q / a;
    if (q != 0) roots[count++] = c / q;
    if (count == 2 && roots[1] < roots[0]) std::swap(roots[0], roots[1]);
  }
  for (int i = 0; i < count; ++i) {
    if (roots[i] > lo && roots[i] < hi && accept(roots[i])) return roots[i];
  }
  return std::nullopt;
}

}  // namespace

const char* SurfaceTypeName(SurfaceType type) {
  switch (type) {
    case SurfaceType::kPlane:
      return "plane";
    case SurfaceType::kCylinder:
      return "cylinder";
    case SurfaceType::kHull:
      return "hull";
  }
  return "plane";
}

SurfaceType SurfaceTypeFromName(const std::string& name, const std::string& context) {
  if (name == "plane") return SurfaceType::kPlane;
  if (name == "cylinder") return SurfaceType::kCylinder;
  if (name == "hull") return SurfaceType::kHull;
  UWS_THROW(context, ": type must be plane, cylinder or hull (got '", name, "')");
}

std::optional<double> Surface::IntersectLocal(const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                                              double lo, double hi) const {
  switch (type) {
    case SurfaceType::kPlane: {
      if (std::abs(d.z()) < 1e-15) return std::nullopt;
      const double lambda = -o.z() / d.z();
      if (!(lambda > lo && lambda < hi)) return std::nullopt;
      if (!InRectangle(o + lambda * d, size_x, size_y)) return std::nullopt;
      return lambda;
    }
    case SurfaceType::kCylinder: {
      const double a = d.x() * d.x() + d.y() * d.y();
      const double b = 2 * (o.x() * d.x() + o.y() * d.y());
      const double c = o.x() * o.x() + o.y() * o.y() - radius * radius;
      return QuadraticRoot(a, b, c, lo, hi,
                           [&](double l) { return std::abs(o.z() + l * d.z()) <= 0.5 * length; });
    }
    case SurfaceType::kHull: {
      // z = k/2 x^2  ->  k/2 (o_x + l d_x)^2 - (o_z + l d_z) = 0
      const double k = 0.5 * curvature;
      const double a = k * d.x() * d.x();
      const double b = 2 * k * o.x() * d.x() - d.z();
      const double c = k * o.x() * o.x() - o.z();
      return QuadraticRoot(a, b, c, lo, hi, [&](double l) {
        const Eigen::Vector3d p = o + l * d;
        return std::abs(p.y()) <= 0.5 * size_y && std::abs(p.x()) <= 0.5 * size_x;
      });
    }
  }
  return std::nullopt;
}

Eigen::Vector3d Surface::NormalLocal(const Eigen::Vector3d& p) const {
  switch (type) {
    case SurfaceType::kPlane:
      return Eigen::Vector3d::UnitZ();
    case SurfaceType::kCylinder:
      return Eigen::Vector3d(p.x(), p.y(), 0).normalized();
    case SurfaceType::kHull:
      return Eigen::Vector3d(-curvature * p.x(), 0, 1).normalized();
  }
  return Eigen::Vector3d::UnitZ();
}

Eigen::Vector2d Surface::TextureCoordinates(const Eigen::Vector3d& p) const {
  switch (type) {
    case SurfaceType::kPlane:
      return p.head<2>();
    case SurfaceType::kCylinder:
      return {radius * std::atan2(p.y(), p.x()), p.z()};
    case SurfaceType::kHull: {
      // Arc length of z = k/2 x^2 from 0 to x.
      const double k = curvature, x = p.x();
      if (std::abs(k) < 1e-12) return {x, p.y()};
      const double kx = k * x, root = std::sqrt(1 + kx * kx);
      return {0.5 * (x * root + std::asinh(kx) / k), p.y()};
    }
  }
  return p.head<2>();
}

double Surface::ImplicitResidual(const Eigen::Vector3d& p) const {
  switch (type) {
    case SurfaceType::kPlane:
      return p.z();
    case SurfaceType::kCylinder:
      return std::hypot(p.x(), p.y()) - radius;
    case SurfaceType::kHull:
      return p.z() - 0.5 * curvature * p.x() * p.x();
  }
  return 0.0;
}

void Surface::Check(const std::string& context) const {
  UWS_CHECK(!name.empty(), context, ": name must not be empty");
  UWS_CHECK(world_from_surface.translation.allFinite() &&
                world_from_surface.rotation.coeffs().allFinite(),
            context, ": world_from_surface must be finite");
  if (type == SurfaceType::kCylinder) {
    UWS_CHECK(std::isfinite(radius) && radius > 0, context, ": radius must be positive");
    UWS_CHECK(std::isfinite(length) && length > 0, context, ": length must be positive");
  } else {
    UWS_CHECK(std::isfinite(size_x) && size_x > 0 && std::isfinite(size_y) && size_y > 0, context,
              ": size must be positive");
  }
  if (type == SurfaceType::kHull) {
    UWS_CHECK(std::isfinite(curvature), context, ": curvature must be finite");
  }
  texture.Check(context + ".texture");
}

std::optional<Hit> Scene::Intersect(const Eigen::Vector3d& origin_world,
                                    const Eigen::Vector3d& direction_world, double min_lambda,
                                    double max_lambda) const {
  std::optional<Hit> best;
  double hi = max_lambda;
  Eigen::Vector3d best_local = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < surfaces.size(); ++i) {
    const Surface& surface = surfaces[i];
    Eigen::Matrix3d stale;
    const Eigen::Matrix3d& surface_R_world = surface.CachedRotation(&stale);
    const Eigen::Vector3d o =
        surface_R_world * (origin_world - surface.world_from_surface.translation);
    const Eigen::Vector3d d = surface_R_world * direction_world;
    const auto lambda = surface.IntersectLocal(o, d, min_lambda, hi);
    if (!lambda) continue;
    hi = *lambda;
    best = Hit{};
    best->lambda = *lambda;
    best->surface = static_cast<int>(i);
    best_local = o + *lambda * d;
  }
  if (!best) return best;
  const Surface& surface = surfaces[best->surface];
  best->point_world = origin_world + best->lambda * direction_world;
  best->normal_world = surface.world_from_surface.rotation * surface.NormalLocal(best_local);
  best->texture_coordinates = surface.TextureCoordinates(best_local);
  return best;
}

bool Scene::Occluded(const Eigen::Vector3d& from_world, const Eigen::Vector3d& to_world,
                     int skip_surface) const {
  const Eigen::Vector3d delta = to_world - from_world;
  const double length = delta.norm();
  if (length <= 0) return false;
  const Eigen::Vector3d direction = delta / length;
  // Tolerance relative to the length keeps the target surface itself out.
  const double epsilon = 1e-7 * std::max(1.0, length);
  for (size_t i = 0; i < surfaces.size(); ++i) {
    const Surface& surface = surfaces[i];
    if (static_cast<int>(i) == skip_surface && surface.type == SurfaceType::kPlane) continue;
    Eigen::Matrix3d stale;
    const Eigen::Matrix3d& surface_R_world = surface.CachedRotation(&stale);
    const Eigen::Vector3d o =
        surface_R_world * (from_world - surface.world_from_surface.translation);
    if (surface.IntersectLocal(o, surface_R_world * direction, epsilon, length - epsilon))
      return true;
  }
  return false;
}

void Surface::Prepare() {
  surface_R_world_ = world_from_surface.RotationMatrix().transpose();
  cached_rotation_ = world_from_surface.rotation;
  texture.Prepare();
}

Eigen::Matrix3d Surface::SurfaceRWorld() const {
  Eigen::Matrix3d stale;
  return CachedRotation(&stale);
}

const Eigen::Matrix3d& Surface::CachedRotation(Eigen::Matrix3d* stale) const {
  if (cached_rotation_.coeffs() == world_from_surface.rotation.coeffs()) return surface_R_world_;
  *stale = world_from_surface.RotationMatrix().transpose();
  return *stale;
}

void Scene::Prepare() {
  for (auto& surface : surfaces) surface.Prepare();
}

void Scene::Check(const std::string& context) const {
  std::set<std::string> names;
  for (size_t i = 0; i < surfaces.size(); ++i) {
    surfaces[i].Check(context + ": surfaces[" + std::to_string(i) + "]");
    UWS_CHECK(names.insert(surfaces[i].name).second, context, ": duplicate surface name '",
              surfaces[i].name, "'");
  }
}

}  // namespace uwscan::sim
