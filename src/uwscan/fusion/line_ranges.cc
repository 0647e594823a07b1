#include "uwscan/fusion/line_ranges.h"

#include <cmath>
#include <utility>

#include "uwscan/util/error.h"

namespace uwscan::fusion {

void LineRangeOptions::Check() const {
  UWS_CHECK(max_offset_m > 0 && base_sigma_m > 0 && min_slope >= 0 && slope_neighbours >= 1,
            "line ranges: max_offset_m and base_sigma_m must be > 0, min_slope >= 0, "
            "slope_neighbours >= 1");
  UWS_CHECK(max_relative_disagreement > 0, "line ranges: max_relative_disagreement must be > 0");
}

std::vector<vo::RangeConstraint> LineRangeConstraints(const Camera& camera,
                                                      const vo::SparseMap& map,
                                                      const Rigid3d& camera_from_world,
                                                      const laser::Profile& profile,
                                                      const LineRangeOptions& options) {
  std::vector<vo::RangeConstraint> ranges;
  if (profile.points.empty() || map.points.empty()) return ranges;
  // Directions of the laser points from the camera centre, for a first
  // choice of the nearest one (the refracted ray's origin is millimetres
  // from the centre, the points metres away).
  std::vector<Eigen::Vector3d> directions;
  directions.reserve(profile.points.size());
  for (const auto& p : profile.points) directions.push_back(p.point_in_camera.normalized());
  for (const auto& [id, point] : map.points) {
    const Eigen::Vector3d in_camera = camera_from_world * point.position_world;
    const double distance = in_camera.norm();
    if (!(in_camera.z() > 0) || !(distance > 0)) continue;
    const Eigen::Vector3d direction = in_camera / distance;
    // Coarse: angle below twice the offset allowed at the point's distance.
    const double min_cos = std::cos(std::min(0.5, 2.0 * options.max_offset_m / distance));
    size_t best = profile.points.size();
    double best_cos = min_cos;
    for (size_t i = 0; i < directions.size(); ++i) {
      const double c = directions[i].dot(direction);
      if (c > best_cos) {
        best_cos = c;
        best = i;
      }
    }
    if (best == profile.points.size()) continue;
    // Exact: along the refracted ray of the pixel the point projects to.
    const auto pixel = camera.Project(in_camera);
    if (!pixel) continue;
    const auto ray = camera.BackProject(*pixel);
    if (!ray) continue;
    // A laser point's range along the ray and its distance from it.
    const auto along_ray = [&ray](const Eigen::Vector3d& p) {
      const Eigen::Vector3d to_p = p - ray->origin;
      const double along = to_p.dot(ray->direction);
      return std::make_pair(along, (to_p - along * ray->direction).norm());
    };
    const auto [range, offset] = along_ray(profile.points[best].point_in_camera);
    if (!(range > 0) || offset > options.max_offset_m) continue;
    const double current = (in_camera - ray->origin).norm();
    if (std::abs(current - range) > options.max_relative_disagreement * range) continue;
    // Steepest change of the range along the line (per metre across the
    // ray) among the neighbouring profile points.
    double slope = options.min_slope;
    const int n = static_cast<int>(profile.points.size());
    for (int j = std::max(0, int(best) - options.slope_neighbours);
         j <= std::min(n - 1, int(best) + options.slope_neighbours); ++j) {
      const auto [along, lateral] = along_ray(profile.points[size_t(j)].point_in_camera);
      if (lateral > 1e-3) slope = std::max(slope, std::abs(along - range) / lateral);
    }
    vo::RangeConstraint constraint;
    constraint.point_id = id;
    constraint.range_m = range;
    constraint.sigma_m = options.base_sigma_m + slope * offset;
    constraint.ray_origin_camera = ray->origin;
    ranges.push_back(constraint);
  }
  return ranges;
}

}  // namespace uwscan::fusion
