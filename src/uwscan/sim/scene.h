// Analytic scene surfaces with texture (issue 3): bounded planes (sea floor,
// checkerboard targets), cylinders (propeller shaft, pipe) and a curved
// ship-hull section. Each surface has a pose world_from_surface; in its own
// frame
//   plane:    z = 0, |x| <= size_x/2, |y| <= size_y/2, front side +z;
//   cylinder: x^2 + y^2 = radius^2, |z| <= length/2, seen from outside;
//   hull:     z = curvature/2 * x^2, |x| <= size_x/2, |y| <= size_y/2 (a
//             section curved about the y axis), front side +z.
// Texture coordinates (s, t) in metres: plane/hull (x, y) (hull x along the
// arc), cylinder (radius * angle, z).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "uwscan/geometry/rigid3d.h"
#include "uwscan/sim/texture.h"

namespace uwscan::sim {

enum class SurfaceType { kPlane, kCylinder, kHull };

const char* SurfaceTypeName(SurfaceType type);
SurfaceType SurfaceTypeFromName(const std::string& name, const std::string& context);

struct Surface {
  std::string name = "floor";
  SurfaceType type = SurfaceType::kPlane;
  Rigid3d world_from_surface;
  double size_x = 10.0;  // plane, hull (m)
  double size_y = 10.0;
  double radius = 0.2;     // cylinder (m)
  double length = 2.0;     // cylinder (m)
  double curvature = 0.2;  // hull (1/m)
  Texture texture;

  // Ray (surface frame) -> smallest lambda in (min_lambda, max_lambda).
  std::optional<double> IntersectLocal(const Eigen::Vector3d& origin,
                                       const Eigen::Vector3d& direction, double min_lambda,
                                       double max_lambda) const;
  // Outward unit normal and texture coordinates at a point on the surface
  // (surface frame).
  Eigen::Vector3d NormalLocal(const Eigen::Vector3d& point) const;
  Eigen::Vector2d TextureCoordinates(const Eigen::Vector3d& point) const;
  // Signed distance-like residual of the implicit equation (0 on the surface).
  double ImplicitResidual(const Eigen::Vector3d& point) const;
  void Check(const std::string& context) const;

  // Caches the rotation matrix and the texture tables (a stale cache is
  // detected and bypassed, only costing speed).
  void Prepare();
  Eigen::Matrix3d SurfaceRWorld() const;
  // The cached matrix, or `stale` filled in when the pose changed since.
  const Eigen::Matrix3d& CachedRotation(Eigen::Matrix3d* stale) const;

 private:
  Eigen::Matrix3d surface_R_world_ = Eigen::Matrix3d::Identity();
  Eigen::Quaterniond cached_rotation_ = Eigen::Quaterniond::Identity();
};

struct Hit {
  double lambda = 0.0;
  int surface = -1;
  Eigen::Vector3d point_world = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal_world = Eigen::Vector3d::UnitZ();  // outward normal of the surface
  Eigen::Vector2d texture_coordinates = Eigen::Vector2d::Zero();
};

struct Scene {
  std::vector<Surface> surfaces;

  // Nearest hit of a world ray with lambda in (min_lambda, max_lambda).
  std::optional<Hit> Intersect(const Eigen::Vector3d& origin_world,
                               const Eigen::Vector3d& direction_world, double min_lambda = 1e-9,
                               double max_lambda = 1e9) const;
  // True if anything blocks the open segment between two world points;
  // `skip_surface` (the surface the segment ends on) is ignored when it
  // cannot shadow itself (planes).
  bool Occluded(const Eigen::Vector3d& from_world, const Eigen::Vector3d& to_world,
                int skip_surface = -1) const;
  void Check(const std::string& context) const;
  void Prepare();
};

}  // namespace uwscan::sim
