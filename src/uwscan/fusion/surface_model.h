// The scene surface as the laser has measured it (metric), used to give
// passive features their depth (thesis §5.4, scale equalisation): a feature
// whose ray crosses a part of the scene the laser has swept gets the range
// of the surface there, so the odometry starts and stays at metric scale
// even on a hovering platform, where two views have too little baseline to
// triangulate.
//
// Profile points are binned by their pixel in a reference view (bounded per
// cell, so memory stays flat); a ray is intersected with a plane fitted to
// the laser points around the place it hits. Where the laser has not swept,
// a ray takes the dominant plane of all points, or a surface measured in
// front of it, continued (a shaft before a hull).
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
  // A local plane is measured only near the points it was fitted on: its
  // hit farther than this from all of them (past the edge of the swept
  // band, or past a shaft's silhouette, where the shaft's tangent plane
  // runs on in front of the hull) is an extrapolation, and is returned as
  // one (extrapolated_sigma_m, Hit::extrapolated). On the simulator's hulls
  // a fifth of the local hits 2-4 cm from every point were off by more
  // than 2 cm, against 2-7 % within 2 cm; 2 and 3 cm tried (BENCHMARKS.md,
  // "Local planes only near their points").
  double max_local_gap_m = 0.03;
  // Where the laser has not swept yet, a ray may take the dominant plane of
  // all laser points (a sea floor, a hull plate), with this uncertainty.
  bool extrapolate_plane = true;
  double extrapolated_sigma_m = 0.02;
  double plane_inlier_m = 0.03;  // RANSAC inlier band of the dominant plane
  double local_sigma_m = 0.002;
  int max_plane_samples = 4000;
  // A surface in front of the dominant plane (a shaft before a hull, a pipe
  // or a chain on a floor), from at least this fraction of the samples,
  // standing out of the plane towards the camera by at least
  // front_min_gap_fraction of the reference view's distance to it (a curved
  // hull's bulge and a sea floor's relief stay within that). Its measured
  // cross-section is continued across the laser sheets that measured it,
  // along the dominant plane (such things mostly run along what is behind
  // them: a shaft along its hull); a ray takes it where it meets it before
  // the plane or before points measured behind it (the hull behind a part
  // of the shaft the laser has not swept, seen from elsewhere).
  double front_min_fraction = 0.02;
  double front_min_gap_fraction = 0.1;
  // The dominant plane's tilt across a narrow band of laser lines is only
  // as good as the poses that placed them over its width: on a tank scan
  // (seed 2311) it was 0.05-0.45 rad off while the band was 5-7 cm wide,
  // 0.008 rad at 11 cm and 0.003-0.005 rad from 14 cm on. A ray that takes
  // the plane while its profiles span less than this across the line gets
  // a provisional hit (Hit::provisional): 2 mm of pose error (the start's
  // settling tolerance) over this width tilts the plane by 13 mrad, 2 cm
  // (extrapolated_sigma_m) at 1.5 m, half the tank view's footprint.
  double settled_plane_width_m = 0.15;
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
    bool provisional = false;  // from the dominant plane on a narrow band
  };
  std::optional<Hit> Intersect(const Eigen::Vector3d& origin,
                               const Eigen::Vector3d& direction) const;
  long size() const { return Binned().points; }
  // Whether the laser points span enough to define the dominant plane.
  bool HasDominantPlane() const { return DominantPlane().has_value(); }
  // How squarely the reference view sees the dominant plane: its distance
  // to the plane over the median distance to the plane's points (1: face
  // on; near 0: edge on, the plane runs through the camera); none without
  // a plane.
  std::optional<double> DominantPlaneViewCosine() const;
  // Whether a surface stands in front of the dominant plane
  // (SurfaceModelOptions::front_min_fraction).
  bool HasFrontSurface() const { return DominantPlane() && !front_points_.empty(); }

  // Points are binned by two bounds of their pixel this far apart in the
  // sine of the air ray's angle (Camera::ProjectBounds), a few 1e-4 px at
  // f = 800 px; by the exact pixel where the bounds fall in two cells.
  static constexpr double kCellBoundsTolerance = 1e-7;

 private:
  std::optional<Eigen::Vector2i> CellOf(const Eigen::Vector3d& point_world) const;
  std::optional<Eigen::Vector3d> IntersectSwept(const Eigen::Vector3d& origin,
                                                const Eigen::Vector3d& direction) const;
  std::optional<Eigen::Vector3d> IntersectLocal(const Eigen::Vector3d& origin,
                                                const Eigen::Vector3d& direction,
                                                const Eigen::Vector2i& cell) const;
  // The cells within search_radius_cells of `cell` (first and last
  // column, row), whose points a local plane around it is fitted on.
  struct CellRange {
    Eigen::Vector2i first, last;
  };
  CellRange Neighbourhood(const Eigen::Vector2i& cell) const;
  std::optional<std::pair<Eigen::Vector3d, Eigen::Vector3d>> FitCell(
      const Eigen::Vector2i& cell) const;
  // Whether a binned point lies within max_local_gap_m of `point` (among
  // the cells a local plane around its cell is fitted on).
  bool NearMeasuredPoint(const Eigen::Vector3d& point) const;

  Camera camera_;
  Rigid3d world_from_reference_, reference_from_world_;
  SurfaceModelOptions options_;
  int cols_ = 0, rows_ = 0;
  // The points binned by their pixel in the reference view. A point is
  // binned (one exact projection through the port) only when the cells are
  // next read: a start-up attempt that stops at HasDominantPlane, building
  // its surface anew from a hundred frames' profiles, reads none of them.
  // Binning later in the same order gives the same cells.
  struct Cells {
    std::vector<std::vector<Eigen::Vector3d>> bins;
    std::vector<int> insert_counts;  // for round-robin replacement in full cells
    long points = 0;                 // in the cells (at most max_points_per_cell each)
    // Running mean depth of the points along the reference view, for the
    // first guess of where a ray lands.
    double depth_sum = 0.0;
  };
  mutable Cells cells_;
  mutable std::vector<Eigen::Vector3d> unbinned_;  // world points, oldest first
  static constexpr size_t kMaxUnbinned = 1 << 18;  // 6 MB, then binned at once
  const Cells& Binned() const;
  // Reservoir sample of all points for the dominant plane (robust fit,
  // refreshed lazily).
  std::vector<Eigen::Vector3d> samples_;
  std::vector<long> sample_profiles_;  // the profile each sample came from
  // Centroids of the profiles (the newest kMaxProfileCentroids).
  static constexpr int kMaxProfileCentroids = 512;
  static constexpr int kRansacIterations = 100;
  std::vector<Eigen::Vector3d> profile_centroids_;
  long profiles_ = 0;
  long seen_ = 0;
  uint64_t random_state_ = 88172645463325252ull;
  mutable bool plane_dirty_ = true;
  // How far the profiles behind the dominant plane spread across the line
  // (2 sqrt(3) standard deviations), for Hit::provisional.
  mutable double plane_width_m_ = 0.0;
  mutable std::optional<std::pair<Eigen::Vector3d, Eigen::Vector3d>> plane_;  // point, normal
  const std::optional<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& DominantPlane() const;
  // The samples in front of the dominant plane and the direction their
  // cross-section is continued along (refreshed with plane_); empty if too
  // few or not swept far enough.
  mutable std::vector<Eigen::Vector3d> front_points_;
  mutable Eigen::Vector3d extrusion_ = Eigen::Vector3d::UnitX();
  void FindFrontSurface() const;
  std::optional<double> IntersectFront(const Eigen::Vector3d& origin,
                                       const Eigen::Vector3d& direction) const;
  // How near the ray must pass a cross-section point: 1 cm, plus 2 % of
  // how far the cross-section is carried along the extrusion. The surface
  // is where kFrontMinSupport such points first come within
  // plane_inlier_m along the ray: the median of those within
  // kFrontDepthBand_m from there.
  static constexpr double kFrontTolerance_m = 0.01, kFrontToleranceSlope = 0.02;
  static constexpr int kFrontMinSupport = 3;
  static constexpr double kFrontDepthBand_m = 0.1;
  long profile_count_ = 0;
};

}  // namespace uwscan::fusion
