#include "uwscan/fusion/surface_model.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "uwscan/util/error.h"

namespace uwscan::fusion {

void SurfaceModelOptions::Check() const {
  UWS_CHECK(cell_px >= 2 && max_points_per_cell >= 4 && search_radius_cells >= 0 && min_points >= 3,
            "surface model: invalid options");
  UWS_CHECK(min_local_width_m >= 0 && min_plane_width_m >= 0 && max_plane_rms_m > 0 &&
                max_local_gap_m > 0 && settled_plane_width_m >= 0,
            "surface model: invalid fit thresholds");
  UWS_CHECK(front_min_fraction > 0 && front_min_fraction <= 1 && front_min_gap_fraction > 0,
            "surface model: invalid thresholds of the surface in front");
}

SurfaceModel::SurfaceModel(const Camera& camera, const Rigid3d& world_from_reference,
                           const SurfaceModelOptions& options)
    : camera_(camera),
      world_from_reference_(world_from_reference),
      reference_from_world_(world_from_reference.Inverse()),
      options_(options) {
  options_.Check();
  cols_ = (camera_.width + options_.cell_px - 1) / options_.cell_px;
  rows_ = (camera_.height + options_.cell_px - 1) / options_.cell_px;
  cells_.bins.resize(static_cast<size_t>(cols_) * rows_);
  cells_.insert_counts.assign(cells_.bins.size(), 0);
}

namespace {

// The cell a pixel falls in, unclamped, and which side of the image's far
// edges it is on. Pixels with the same key lie in one rectangle, and so
// does the segment between them.
struct CellKey {
  double column, row;
  bool left_of_right_edge, above_bottom_edge;
  bool operator==(const CellKey& other) const {
    return column == other.column && row == other.row &&
           left_of_right_edge == other.left_of_right_edge &&
           above_bottom_edge == other.above_bottom_edge;
  }
};

CellKey KeyOf(const Eigen::Vector2d& pixel, const Camera& camera, int cell_px) {
  return {std::floor((pixel.x() + 0.5) / cell_px), std::floor((pixel.y() + 0.5) / cell_px),
          pixel.x() <= camera.width - 0.5, pixel.y() <= camera.height - 0.5};
}

}  // namespace

std::optional<Eigen::Vector2i> SurfaceModel::CellOf(const Eigen::Vector3d& point_world) const {
  const Eigen::Vector3d point = reference_from_world_ * point_world;
  // Most points are placed by two bounds of their exact pixel, at half
  // its cost; those near a cell's edge by the pixel itself.
  std::optional<CellKey> key;
  if (const auto bounds = camera_.ProjectBounds(point, kCellBoundsTolerance)) {
    const CellKey low = KeyOf(bounds->first, camera_, options_.cell_px);
    if (low == KeyOf(bounds->second, camera_, options_.cell_px)) key = low;
  }
  if (!key) {
    const auto pixel = camera_.Project(point);
    if (!pixel) return std::nullopt;
    key = KeyOf(*pixel, camera_, options_.cell_px);
  }
  // In the image (Camera::InImage) exactly when on the near side of all four edges.
  if (!(key->column >= 0 && key->row >= 0 && key->left_of_right_edge && key->above_bottom_edge))
    return std::nullopt;
  return Eigen::Vector2i(std::min(static_cast<int>(key->column), cols_ - 1),
                         std::min(static_cast<int>(key->row), rows_ - 1));
}

void SurfaceModel::AddProfile(const Rigid3d& world_from_camera, const laser::Profile& profile) {
  if (static_cast<int>(profile.points.size()) >= options_.min_points) {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (const auto& p : profile.points) centroid += p.point_in_camera;
    centroid = world_from_camera * (centroid / profile.points.size());
    // The newest profiles are the ones that matter for the sweep's width.
    if (static_cast<int>(profile_centroids_.size()) < kMaxProfileCentroids)
      profile_centroids_.push_back(centroid);
    else
      profile_centroids_[profiles_++ % kMaxProfileCentroids] = centroid;
  }
  const long profile_id = profile_count_++;
  for (const auto& p : profile.points) {
    const Eigen::Vector3d world = world_from_camera * p.point_in_camera;
    // Reservoir sampling (xorshift) keeps a uniform bounded sample.
    ++seen_;
    if (static_cast<int>(samples_.size()) < options_.max_plane_samples) {
      samples_.push_back(world);
      sample_profiles_.push_back(profile_id);
    } else {
      random_state_ ^= random_state_ << 13;
      random_state_ ^= random_state_ >> 7;
      random_state_ ^= random_state_ << 17;
      const long slot = static_cast<long>(random_state_ % static_cast<uint64_t>(seen_));
      if (slot < options_.max_plane_samples) {
        samples_[slot] = world;
        sample_profiles_[slot] = profile_id;
      }
    }
    plane_dirty_ = true;
    unbinned_.push_back(world);
  }
  if (unbinned_.size() >= kMaxUnbinned) Binned();
}

const SurfaceModel::Cells& SurfaceModel::Binned() const {
  for (const Eigen::Vector3d& world : unbinned_) {
    const auto cell = CellOf(world);
    if (!cell) continue;
    const size_t index = static_cast<size_t>(cell->y()) * cols_ + cell->x();
    auto& bucket = cells_.bins[index];
    // Full cells replace their points round robin: newest measurements win,
    // memory stays bounded.
    if (static_cast<int>(bucket.size()) < options_.max_points_per_cell) {
      bucket.push_back(world);
      ++cells_.points;
      cells_.depth_sum += (reference_from_world_ * world).z();
    } else {
      bucket[cells_.insert_counts[index] % options_.max_points_per_cell] = world;
    }
    ++cells_.insert_counts[index];
  }
  if (unbinned_.capacity() > 65536)
    unbinned_ = {};  // after a start-up's hundred profiles, back to one frame's
  else
    unbinned_.clear();
  return cells_;
}

SurfaceModel::CellRange SurfaceModel::Neighbourhood(const Eigen::Vector2i& cell) const {
  const int radius = options_.search_radius_cells;
  return {Eigen::Vector2i(std::max(0, cell.x() - radius), std::max(0, cell.y() - radius)),
          Eigen::Vector2i(std::min(cols_ - 1, cell.x() + radius),
                          std::min(rows_ - 1, cell.y() + radius))};
}

std::optional<std::pair<Eigen::Vector3d, Eigen::Vector3d>> SurfaceModel::FitCell(
    const Eigen::Vector2i& cell) const {
  std::vector<const Eigen::Vector3d*> local;
  const CellRange around = Neighbourhood(cell);
  for (int r = around.first.y(); r <= around.last.y(); ++r) {
    for (int c = around.first.x(); c <= around.last.x(); ++c) {
      for (const auto& p : cells_.bins[static_cast<size_t>(r) * cols_ + c]) local.push_back(&p);
    }
  }
  if (static_cast<int>(local.size()) < options_.min_points) return std::nullopt;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto* p : local) centroid += *p;
  centroid /= local.size();
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const auto* p : local) scatter += (*p - centroid) * (*p - centroid).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter);
  const Eigen::Vector3d eigenvalues = solver.eigenvalues();  // ascending
  if (!(std::sqrt(12.0 * eigenvalues(1) / local.size()) >= options_.min_local_width_m)) {
    return std::nullopt;
  }
  if (!(std::sqrt(std::max(0.0, eigenvalues(0)) / local.size()) <= options_.max_plane_rms_m)) {
    return std::nullopt;
  }
  return std::pair{centroid, Eigen::Vector3d(solver.eigenvectors().col(0))};
}

bool SurfaceModel::NearMeasuredPoint(const Eigen::Vector3d& point) const {
  const auto cell = CellOf(point);
  if (!cell) return false;
  const double gap_squared = options_.max_local_gap_m * options_.max_local_gap_m;
  const CellRange around = Neighbourhood(*cell);
  for (int r = around.first.y(); r <= around.last.y(); ++r) {
    for (int c = around.first.x(); c <= around.last.x(); ++c) {
      for (const auto& p : cells_.bins[static_cast<size_t>(r) * cols_ + c]) {
        if ((p - point).squaredNorm() <= gap_squared) return true;
      }
    }
  }
  return false;
}

std::optional<Eigen::Vector3d> SurfaceModel::IntersectLocal(const Eigen::Vector3d& origin,
                                                            const Eigen::Vector3d& direction,
                                                            const Eigen::Vector2i& cell) const {
  const auto plane = FitCell(cell);
  if (!plane) return std::nullopt;
  const auto& [centroid, normal] = *plane;
  const double denominator = normal.dot(direction);
  if (!(std::abs(denominator) > 1e-6)) return std::nullopt;
  const double lambda = normal.dot(centroid - origin) / denominator;
  if (!(lambda > 0)) return std::nullopt;
  return origin + lambda * direction;
}

const std::optional<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& SurfaceModel::DominantPlane()
    const {
  if (!plane_dirty_) return plane_;
  plane_dirty_ = false;
  plane_.reset();
  if (static_cast<int>(samples_.size()) < options_.min_points) return plane_;
  // RANSAC first, so that a shaft in front of a hull (or a target on a
  // floor) does not tilt the plane most of the points lie on; then
  // iteratively reweighted total least squares (Huber, 5 mm, within the
  // inlier band) from its inliers.
  std::vector<double> weights(samples_.size(), 1.0);
  {
    const size_t n = samples_.size();
    const size_t score_stride = std::max<size_t>(1, n / 500);
    uint64_t state = 0x9E3779B97F4A7C15ull;  // deterministic
    const auto pick = [&state, n] {
      state ^= state << 13, state ^= state >> 7, state ^= state << 17;
      return static_cast<size_t>(state % n);
    };
    int best_score = -1;
    Eigen::Vector3d best_point = Eigen::Vector3d::Zero(), best_normal = Eigen::Vector3d::UnitZ();
    for (int iteration = 0; iteration < kRansacIterations; ++iteration) {
      const Eigen::Vector3d& a = samples_[pick()];
      const Eigen::Vector3d normal = (samples_[pick()] - a).cross(samples_[pick()] - a);
      if (!(normal.norm() > 1e-9)) continue;
      const Eigen::Vector3d unit = normal.normalized();
      int score = 0;
      for (size_t i = 0; i < n; i += score_stride)
        score += std::abs(unit.dot(samples_[i] - a)) <= options_.plane_inlier_m;
      if (score > best_score) best_score = score, best_point = a, best_normal = unit;
    }
    if (best_score < 0) return plane_;  // every sample collinear: no plane
    for (size_t i = 0; i < n; ++i)
      weights[i] = std::abs(best_normal.dot(samples_[i] - best_point)) <= options_.plane_inlier_m;
  }
  for (int iteration = 0; iteration < 4; ++iteration) {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    double total = 0.0;
    for (size_t i = 0; i < samples_.size(); ++i)
      centroid += weights[i] * samples_[i], total += weights[i];
    centroid /= total;
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    for (size_t i = 0; i < samples_.size(); ++i) {
      const Eigen::Vector3d d = samples_[i] - centroid;
      scatter += weights[i] * d * d.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter);
    if (!(std::sqrt(12.0 * solver.eigenvalues()(1) / total) >= options_.min_plane_width_m)) {
      return plane_;
    }
    const Eigen::Vector3d normal = solver.eigenvectors().col(0);
    // One curved profile (a hull, a shaft in front of it) also spreads
    // across its longest direction, but within the laser sheet: its plane
    // would be the sheet. The profiles themselves must lie apart across the
    // line, in the plane.
    const Eigen::Vector3d across = normal.cross(solver.eigenvectors().col(2)).normalized();
    double sum = 0.0, sum_squares = 0.0;
    for (const auto& c : profile_centroids_) {
      const double x = across.dot(c - centroid);
      sum += x, sum_squares += x * x;
    }
    const double count = std::max<double>(profile_centroids_.size(), 1.0);
    const double variance = sum_squares / count - (sum / count) * (sum / count);
    plane_width_m_ = std::sqrt(12.0 * std::max(variance, 0.0));
    if (!(plane_width_m_ >= options_.min_plane_width_m)) {
      plane_.reset();
      return plane_;
    }
    plane_ = std::pair{centroid, normal};
    for (size_t i = 0; i < samples_.size(); ++i) {
      // Huber within the inlier band, nothing beyond: a Huber weight alone
      // lets far points (a shaft) grow in the scatter as w r^2 = 5 mm x r.
      const double r = std::abs(normal.dot(samples_[i] - centroid));
      weights[i] = r <= 0.005 ? 1.0 : (r <= options_.plane_inlier_m ? 0.005 / r : 0.0);
    }
  }
  if (plane_) FindFrontSurface();
  return plane_;
}

std::optional<double> SurfaceModel::DominantPlaneViewCosine() const {
  const auto& plane = DominantPlane();
  if (!plane) return std::nullopt;
  const Eigen::Vector3d& eye = world_from_reference_.translation;
  const auto& [point, normal] = *plane;
  std::vector<double> distances;
  for (const auto& sample : samples_) {
    if (std::abs(normal.dot(sample - point)) <= options_.plane_inlier_m)
      distances.push_back((sample - eye).norm());
  }
  if (distances.empty()) return std::nullopt;
  const auto middle = distances.begin() + static_cast<long>(distances.size() / 2);
  std::nth_element(distances.begin(), middle, distances.end());
  if (!(*middle > 0)) return std::nullopt;
  return std::min(1.0, std::abs(normal.dot(eye - point)) / *middle);
}

void SurfaceModel::FindFrontSurface() const {
  front_points_.clear();
  const Eigen::Vector3d centre = world_from_reference_.translation;
  const auto& [plane_point, plane_normal] = *plane_;
  // The samples well in front of the dominant plane: on the reference
  // camera's side, above an empty gap of a fraction of the camera's distance
  // to it (a shaft before a hull, not a curved hull's bulge or a sea floor's
  // relief, which rise from the plane without one; a few mixed pixels at a
  // silhouette may lie in it).
  const double camera_side = plane_normal.dot(centre - plane_point);
  const double gap = options_.front_min_gap_fraction * std::abs(camera_side);
  std::vector<double> height(samples_.size()), heights;  // towards the camera; those off the plane
  for (size_t i = 0; i < samples_.size(); ++i) {
    height[i] = std::copysign(1.0, camera_side) * plane_normal.dot(samples_[i] - plane_point);
    if (height[i] > options_.plane_inlier_m) heights.push_back(height[i]);
  }
  std::sort(heights.begin(), heights.end());
  const size_t needed = static_cast<size_t>(
      std::max<double>(options_.min_points, options_.front_min_fraction * samples_.size()));
  const size_t stray = std::max<size_t>(3, samples_.size() / 500);
  std::optional<double> above;
  for (size_t j = 0; j < heights.size() && heights.size() - j > needed; ++j) {
    const double start = j == 0 ? options_.plane_inlier_m : heights[j - 1];
    const auto end = std::upper_bound(heights.begin(), heights.end(), start + gap);
    if (static_cast<size_t>(end - heights.begin()) - j <= stray &&
        static_cast<size_t>(heights.end() - end) >= needed) {
      above = start + gap;
      break;
    }
  }
  if (!above) return;
  std::unordered_map<long, std::vector<size_t>> profiles;  // with a point in front
  for (size_t i = 0; i < samples_.size(); ++i) {
    if (!(height[i] > *above)) continue;
    front_points_.push_back(samples_[i]);
    profiles[sample_profiles_[i]];
  }
  // The laser sheets that measured it: each such profile's samples, on
  // whichever surface, span its sheet. The surface is continued across
  // them, the way the sweep moves the line.
  for (size_t i = 0; i < samples_.size(); ++i) {
    const auto it = profiles.find(sample_profiles_[i]);
    if (it != profiles.end()) it->second.push_back(i);
  }
  Eigen::Matrix3d sheets = Eigen::Matrix3d::Zero();
  for (const auto& [profile, members] : profiles) {
    if (members.size() < 5) continue;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (size_t i : members) mean += samples_[i];
    mean /= members.size();
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    for (size_t i : members) scatter += (samples_[i] - mean) * (samples_[i] - mean).transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> fit(scatter);
    // A straight run does not tell its sheet.
    if (!(fit.eigenvalues()(1) > 0.01 * fit.eigenvalues()(2))) continue;
    sheets += fit.eigenvectors().col(0) * fit.eigenvectors().col(0).transpose();
  }
  if (!(sheets.trace() > 0)) {
    front_points_.clear();
    return;
  }
  // Across the sheets, and along the dominant surface: what lies in front
  // of a hull, a floor or a wall (a shaft, a pipe, a chain, a board) mostly
  // runs along it.
  const Eigen::Vector3d across =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(sheets).eigenvectors().col(2);
  extrusion_ = across - plane_normal.dot(across) * plane_normal;
  if (!(extrusion_.norm() > 0.5)) {  // the sheets lie along the plane
    front_points_.clear();
    return;
  }
  extrusion_.normalize();
}

std::optional<double> SurfaceModel::IntersectFront(const Eigen::Vector3d& origin,
                                                   const Eigen::Vector3d& direction) const {
  // Along the extrusion the front surface's cross-section stays the same:
  // the ray, seen along it, passes the measured cross-section where it meets
  // the surface (the nearest of them: that surface hides what is behind).
  const Eigen::Vector3d d = direction - extrusion_.dot(direction) * extrusion_;
  const double d2 = d.squaredNorm();
  if (!(d2 > 1e-6)) return std::nullopt;
  std::vector<double> lambdas;
  for (const Eigen::Vector3d& p : front_points_) {
    const Eigen::Vector3d w = p - origin;
    const double along = extrusion_.dot(w);
    const Eigen::Vector3d w_across = w - along * extrusion_;
    const double lambda = w_across.dot(d) / d2;
    if (!(lambda > 0)) continue;
    // The farther the cross-section is carried, the less exactly it fits.
    const double carried = std::abs(along - lambda * extrusion_.dot(direction));
    const double tolerance = kFrontTolerance_m + kFrontToleranceSlope * carried;
    if ((w_across - lambda * d).squaredNorm() <= tolerance * tolerance) lambdas.push_back(lambda);
  }
  if (static_cast<int>(lambdas.size()) < kFrontMinSupport) return std::nullopt;
  std::sort(lambdas.begin(), lambdas.end());
  // The nearest cluster of kFrontMinSupport within a few centimetres, and
  // the median of the points up to kFrontDepthBand_m beyond its start (a
  // cross-section smeared by the poses would otherwise be taken at its near
  // edge).
  for (size_t i = 0; i + kFrontMinSupport <= lambdas.size(); ++i) {
    if (lambdas[i + kFrontMinSupport - 1] - lambdas[i] > options_.plane_inlier_m) continue;
    size_t end = i;
    while (end < lambdas.size() && lambdas[end] - lambdas[i] <= kFrontDepthBand_m) ++end;
    return lambdas[i + (end - i) / 2];
  }
  return std::nullopt;
}

std::optional<SurfaceModel::Hit> SurfaceModel::Intersect(const Eigen::Vector3d& origin,
                                                         const Eigen::Vector3d& direction) const {
  if (Binned().points < options_.min_points) return std::nullopt;
  // A local plane's hit is measured where the laser points are,
  // extrapolated beyond them (max_local_gap_m).
  const auto local = IntersectSwept(origin, direction);
  if (!options_.extrapolate_plane) {
    if (!local || !NearMeasuredPoint(*local)) return std::nullopt;
    return Hit{*local, options_.local_sigma_m, false};
  }
  const auto& plane = DominantPlane();  // refreshes the surface in front too
  // A surface in front hides what lies behind it where the ray meets it:
  // the dominant plane, and also points measured behind a part of it the
  // laser has not swept (the hull behind a shaft, seen from elsewhere).
  double front = std::numeric_limits<double>::infinity();
  if (!front_points_.empty()) front = IntersectFront(origin, direction).value_or(front);
  if (local) {
    const double range = (*local - origin).norm();
    if (front < range * (1.0 - options_.front_min_gap_fraction))
      return Hit{origin + front * direction, options_.extrapolated_sigma_m, true};
    if (!NearMeasuredPoint(*local)) return Hit{*local, options_.extrapolated_sigma_m, true};
    return Hit{*local, options_.local_sigma_m, false};
  }
  if (!plane) return std::nullopt;
  double nearest = front;
  const double denominator = plane->second.dot(direction);
  if (std::abs(denominator) > 1e-3) {
    const double lambda = plane->second.dot(plane->first - origin) / denominator;
    if (lambda > 0 && lambda < nearest) nearest = lambda;
  }
  if (!std::isfinite(nearest)) return std::nullopt;
  return Hit{origin + nearest * direction, options_.extrapolated_sigma_m, true,
             nearest != front && plane_width_m_ < options_.settled_plane_width_m};
}

std::optional<Eigen::Vector3d> SurfaceModel::IntersectSwept(
    const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) const {
  // First guess: the mean depth of the measured surface along the
  // reference view; then refine the cell from the local plane's hit.
  const Eigen::Vector3d axis = world_from_reference_.rotation * Eigen::Vector3d::UnitZ();
  const double mean_depth = cells_.depth_sum / cells_.points;  // binned by Intersect
  const double towards = axis.dot(direction);
  if (!(towards > 1e-6)) return std::nullopt;
  const double lambda =
      (mean_depth - axis.dot(origin - world_from_reference_.translation)) / towards;
  auto cell = CellOf(origin + std::max(lambda, 0.0) * direction);
  std::optional<Eigen::Vector3d> hit;
  for (int iteration = 0; iteration < 3 && cell; ++iteration) {
    hit = IntersectLocal(origin, direction, *cell);
    if (!hit) return std::nullopt;
    const auto next = CellOf(*hit);
    if (!next) return std::nullopt;
    if (*next == *cell) return hit;
    cell = next;
  }
  return hit;
}

}  // namespace uwscan::fusion
