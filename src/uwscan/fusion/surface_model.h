// The scene surface as the laser has measured it (metric), used to give
// passive features their depth (thesis §5.4, scale equalisation): a feature
// whose ray crosses a part of the scene the laser has swept gets the range
// of the surface there, so the odometry starts and stays at metric scale
// even on a hovering platform, where two views have too little baseline to
// triangulate.
//
// Profile points are binned by their pixel in a reference view (bounded per
// cell, so memory stays flat); a ray is intersected with a plane fitted to
// the laser points around the place it hits.
#pragma once

#include <optional>
#include <vector>

#include "uwscan/geometry/rigid3d.h"
#include "uwscan/laser/profile.h"
#include "uwscan/sensor/camera.h"

namespace uwscan::fusion {

struct SurfaceModelOptions {
  int cell_px = 16;  // bin size in the reference image
  int max_points_per_cell = 48;
  int search_radius_cells = 2;  // neighbourhood for the local plane
  int min_points = 10;
  // The points must spread across the laser line (several profiles), or
  // the plane's tilt is unknown: width (2 sqrt(3) x standard deviation) of
  // the points across their longest direction, locally and for the
  // dominant plane.
  double min_local_width_m = 0.01;
  double min_plane_width_m = 0.05;
  double max_plane_rms_m = 0.01;  // a local fit worse than this is not trusted
  // Where the laser has not swept yet, a ray may take the dominant plane of
  // all laser points (a sea floor, a hull plate), with this uncertainty.
  bool extrapolate_plane = true;
  double extrapolated_sigma_m = 0.02;
  double plane_inlier_m = 0.03;  // RANSAC inlier band of the dominant plane
  double local_sigma_m = 0.002;
  int max_plane_samples = 4000;
  void Check() const;
};

class SurfaceModel {
 public:
  SurfaceModel(const Camera& camera, const Rigid3d& world_from_reference,
               const SurfaceModelOptions& options = {});

  // Adds a profile (camera frame) seen from `world_from_camera`.
  void AddProfile(const Rigid3d& world_from_camera, const laser::Profile& profile);
  // Where a world ray meets the measured surface; nullopt where the laser
  // has not (yet) measured enough around it.
  struct Hit {
    Eigen::Vector3d point;
    double sigma_m = 0.0;
    bool extrapolated = false;
  };
  std::optional<Hit> Intersect(const Eigen::Vector3d& origin,
                               const Eigen::Vector3d& direction) const;
  long size() const { return points_; }
  // Whether the laser points span enough to define the dominant plane.
  bool HasDominantPlane() const { return DominantPlane().has_value(); }

 private:
  std::optional<Eigen::Vector2i> CellOf(const Eigen::Vector3d& point_world) const;
  std::optional<Eigen::Vector3d> IntersectSwept(const Eigen::Vector3d& origin,
                                                const Eigen::Vector3d& direction) const;
  std::optional<Eigen::Vector3d> IntersectLocal(const Eigen::Vector3d& origin,
                                                const Eigen::Vector3d& direction,
                                                const Eigen::Vector2i& cell) const;
  std::optional<std::pair<Eigen::Vector3d, Eigen::Vector3d>> FitCell(
      const Eigen::Vector2i& cell) const;

  Camera camera_;
  Rigid3d world_from_reference_, reference_from_world_;
  SurfaceModelOptions options_;
  int cols_ = 0, rows_ = 0;
  std::vector<std::vector<Eigen::Vector3d>> cells_;
  std::vector<int> insert_counts_;  // for round-robin replacement in full cells
  long points_ = 0;
  // Reservoir sample of all points for the dominant plane (robust fit,
  // refreshed lazily).
  std::vector<Eigen::Vector3d> samples_;
  // Centroids of the profiles (the newest kMaxProfileCentroids).
  static constexpr int kMaxProfileCentroids = 512;
  static constexpr int kRansacIterations = 100;
  std::vector<Eigen::Vector3d> profile_centroids_;
  long profiles_ = 0;
  long seen_ = 0;
  uint64_t random_state_ = 88172645463325252ull;
  mutable bool plane_dirty_ = true;
  mutable std::optional<std::pair<Eigen::Vector3d, Eigen::Vector3d>> plane_;  // point, normal
  const std::optional<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& DominantPlane() const;
  // Running mean depth of the points along the reference view, for the
  // first guess of where a ray lands.
  double depth_sum_ = 0.0;
};

}  // namespace uwscan::fusion
