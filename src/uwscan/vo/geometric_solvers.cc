#include "uwscan/vo/geometric_solvers.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opengv/absolute_pose/CentralAbsoluteAdapter.hpp>
#include <opengv/absolute_pose/NoncentralAbsoluteAdapter.hpp>
#include <opengv/sac/Ransac.hpp>
#include <opengv/sac_problems/absolute_pose/AbsolutePoseSacProblem.hpp>

#include "uwscan/util/error.h"

namespace uwscan::vo {

void RelativePoseOptions::Check() const {
  UWS_CHECK(threshold_rad > 0 && threshold_rad < 0.1, "relative pose threshold out of range");
  UWS_CHECK(confidence > 0 && confidence < 1, "relative pose confidence must be in (0, 1)");
}

void AbsolutePoseOptions::Check() const {
  UWS_CHECK(threshold_rad > 0 && threshold_rad < 0.1, "absolute pose threshold out of range");
  UWS_CHECK(max_iterations >= 1, "absolute pose max_iterations must be >= 1");
}

namespace {

// Ray directions as points on the z = 1 plane (the central approximation).
std::vector<cv::Point2d> NormalisedPoints(const std::vector<Ray>& rays) {
  std::vector<cv::Point2d> points;
  points.reserve(rays.size());
  for (const Ray& ray : rays) {
    const Eigen::Vector3d& d = ray.direction;
    points.emplace_back(d.x() / d.z(), d.y() / d.z());
  }
  return points;
}

}  // namespace

RelativePoseResult EstimateRelativePose(const std::vector<Ray>& rays1,
                                        const std::vector<Ray>& rays2,
                                        const RelativePoseOptions& options) {
  options.Check();
  UWS_CHECK(rays1.size() == rays2.size(), "EstimateRelativePose: ray counts differ");
  RelativePoseResult result;
  if (rays1.size() < 8) return result;
  const std::vector<cv::Point2d> p1 = NormalisedPoints(rays1), p2 = NormalisedPoints(rays2);
  cv::Mat mask;
  const cv::Mat essential = cv::findEssentialMat(p1, p2, 1.0, cv::Point2d(0, 0), cv::RANSAC,
                                                 options.confidence, options.threshold_rad, mask);
  if (essential.rows != 3 || essential.cols != 3) return result;  // none or several
  cv::Mat rotation, translation;
  const int good =
      cv::recoverPose(essential, p1, p2, rotation, translation, 1.0, cv::Point2d(0, 0), mask);
  if (good < 8) return result;
  Eigen::Matrix3d r;
  Eigen::Vector3d t;
  cv::cv2eigen(rotation, r);
  cv::cv2eigen(translation, t);
  result.camera2_from_camera1 = Rigid3d(Eigen::Quaterniond(r), t.normalized());
  result.inliers.assign(rays1.size(), 0);
  for (size_t i = 0; i < rays1.size(); ++i) {
    result.inliers[i] = mask.at<uint8_t>(int(i)) != 0;
    result.num_inliers += result.inliers[i];
  }
  result.success = true;
  return result;
}

std::vector<RelativePoseResult> RelativePosesFromHomography(const std::vector<Ray>& rays1,
                                                            const std::vector<Ray>& rays2,
                                                            const RelativePoseOptions& options) {
  options.Check();
  UWS_CHECK(rays1.size() == rays2.size(), "RelativePosesFromHomography: ray counts differ");
  std::vector<RelativePoseResult> results;
  if (rays1.size() < 8) return results;
  const std::vector<cv::Point2d> p1 = NormalisedPoints(rays1), p2 = NormalisedPoints(rays2);
  cv::Mat mask;
  const cv::Mat homography =
      cv::findHomography(p1, p2, cv::RANSAC, options.threshold_rad, mask, 2000, options.confidence);
  if (homography.empty()) return results;
  std::vector<cv::Mat> rotations, translations, normals;
  cv::decomposeHomographyMat(homography, cv::Mat::eye(3, 3, CV_64F), rotations, translations,
                             normals);
  for (size_t k = 0; k < rotations.size(); ++k) {
    Eigen::Matrix3d r;
    Eigen::Vector3d t;
    cv::cv2eigen(rotations[k], r);
    cv::cv2eigen(translations[k], t);
    if (!(t.norm() > 1e-9)) continue;
    RelativePoseResult result;
    result.camera2_from_camera1 = Rigid3d(Eigen::Quaterniond(r), t.normalized());
    result.inliers.assign(rays1.size(), 0);
    for (size_t i = 0; i < rays1.size(); ++i) {
      result.inliers[i] = mask.at<uint8_t>(int(i)) != 0;
      result.num_inliers += result.inliers[i];
    }
    result.success = true;
    results.push_back(result);
  }
  return results;
}

AbsolutePoseResult EstimateAbsolutePose(const std::vector<Ray>& rays_camera,
                                        const std::vector<Eigen::Vector3d>& points_world,
                                        const AbsolutePoseOptions& options) {
  options.Check();
  UWS_CHECK(rays_camera.size() == points_world.size(), "EstimateAbsolutePose: counts differ");
  AbsolutePoseResult result;
  if (rays_camera.size() < 4) return result;
  opengv::bearingVectors_t bearings;
  opengv::points_t points;
  opengv::translations_t offsets;
  opengv::rotations_t rotations;
  std::vector<int> correspondences;
  for (size_t i = 0; i < rays_camera.size(); ++i) {
    bearings.push_back(rays_camera[i].direction.normalized());
    points.push_back(points_world[i]);
    offsets.push_back(rays_camera[i].origin);
    rotations.push_back(Eigen::Matrix3d::Identity());
    correspondences.push_back(int(i));
  }
  using Problem = opengv::sac_problems::absolute_pose::AbsolutePoseSacProblem;
  opengv::sac::Ransac<Problem> ransac;
  ransac.threshold_ = 1.0 - std::cos(options.threshold_rad);
  ransac.max_iterations_ = options.max_iterations;
  // On the stack: OpenGV's adapters free with Eigen's aligned free, which
  // does not match the plain new of std::make_unique (valgrind).
  std::optional<opengv::absolute_pose::NoncentralAbsoluteAdapter> noncentral;
  std::optional<opengv::absolute_pose::CentralAbsoluteAdapter> central;
  if (options.solver == AbsolutePoseSolver::kGP3P) {
    noncentral.emplace(bearings, correspondences, points, offsets, rotations);
    ransac.sac_model_ = std::make_shared<Problem>(*noncentral, Problem::GP3P, false);
  } else {
    central.emplace(bearings, points);
    ransac.sac_model_ = std::make_shared<Problem>(*central, Problem::KNEIP, false);
  }
  if (!ransac.computeModel() || ransac.inliers_.size() < 4) return result;
  // OpenGV returns the viewpoint in the world: [R | c] = world_from_camera.
  const opengv::transformation_t& model = ransac.model_coefficients_;
  const Eigen::Matrix3d world_from_camera_r = model.block<3, 3>(0, 0);
  if (!world_from_camera_r.allFinite() || !model.col(3).allFinite()) return result;
  result.camera_from_world =
      Rigid3d(Eigen::Quaterniond(world_from_camera_r), model.col(3)).Inverse();
  result.inliers.assign(rays_camera.size(), 0);
  for (int i : ransac.inliers_) result.inliers[size_t(i)] = 1;
  result.num_inliers = int(ransac.inliers_.size());
  result.success = true;
  return result;
}

double MaxRayAngle(const std::vector<Ray>& rays_world) {
  double min_cos = 1.0;
  for (size_t i = 0; i < rays_world.size(); ++i) {
    for (size_t j = i + 1; j < rays_world.size(); ++j) {
      min_cos = std::min(
          min_cos, rays_world[i].direction.normalized().dot(rays_world[j].direction.normalized()));
    }
  }
  return std::acos(std::clamp(min_cos, -1.0, 1.0));
}

}  // namespace uwscan::vo
