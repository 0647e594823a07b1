// Minimal solvers of the visual odometry (thesis §5.2) on rays from
// Camera::BackProject, so the same code serves pinhole and flat-port
// cameras:
//  - relative pose: Nistér's five-point algorithm in RANSAC (OpenCV) on the
//    central approximation of the rays (water directions, origins dropped);
//    the refractive model then refines it in the two-view bundle adjustment;
//  - absolute pose: P3P (Kneip, central) or generalised P3P (gp3p, Kneip
//    2013, exact for the refracted rays with their origins on the port) in
//    RANSAC (OpenGV);
//  - triangulation of rays in the world frame (least squares).
#pragma once

#include <optional>
#include <vector>

#include "uwscan/geometry/rigid3d.h"
#include "uwscan/sensor/camera.h"

namespace uwscan::vo {

struct RelativePoseOptions {
  double threshold_rad = 1.5 / 785.0;  // RANSAC threshold as an angle (~ px / f)
  double confidence = 0.999;
  void Check() const;
};

struct RelativePoseResult {
  bool success = false;
  Rigid3d camera2_from_camera1;  // unit translation
  std::vector<char> inliers;
  int num_inliers = 0;
};

// rays1[i] and rays2[i] see the same point (camera frames).
RelativePoseResult EstimateRelativePose(const std::vector<Ray>& rays1,
                                        const std::vector<Ray>& rays2,
                                        const RelativePoseOptions& options = {});

// The (up to four) motions of a homography between the rays (OpenCV
// decomposeHomographyMat on the central approximation): a near-planar sea
// floor makes the five-point solution ambiguous, so the initialisation
// refines every candidate and keeps the best. Translations are unit.
std::vector<RelativePoseResult> RelativePosesFromHomography(
    const std::vector<Ray>& rays1, const std::vector<Ray>& rays2,
    const RelativePoseOptions& options = {});

enum class AbsolutePoseSolver { kP3P, kGP3P };

struct AbsolutePoseOptions {
  AbsolutePoseSolver solver = AbsolutePoseSolver::kGP3P;
  double threshold_rad = 2.0 / 785.0;
  int max_iterations = 200;
  void Check() const;
};

struct AbsolutePoseResult {
  bool success = false;
  Rigid3d camera_from_world;
  std::vector<char> inliers;
  int num_inliers = 0;
};

AbsolutePoseResult EstimateAbsolutePose(const std::vector<Ray>& rays_camera,
                                        const std::vector<Eigen::Vector3d>& points_world,
                                        const AbsolutePoseOptions& options = {});

// Largest angle (rad) between any two ray directions.
double MaxRayAngle(const std::vector<Ray>& rays_world);

}  // namespace uwscan::vo
