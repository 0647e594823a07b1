// Similarity alignment of two point sets (Umeyama 1991): finds s, R, t
// minimising sum |target_i - (s R source_i + t)|^2. Used to compare a
// monocular trajectory (known up to scale) with ground truth.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>
#include <vector>

#include "uwscan/geometry/rigid3d.h"

namespace uwscan {

struct Sim3d {
  double scale = 1.0;
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  Eigen::Vector3d operator*(const Eigen::Vector3d& point) const {
    return scale * (rotation * point) + translation;
  }
  // Applies the similarity to a pose world_from_camera (the camera keeps its
  // orientation relative to the scaled world).
  Rigid3d operator*(const Rigid3d& pose) const {
    return Rigid3d(rotation * pose.rotation, *this * pose.translation);
  }
};

// target ~ sim * source. Needs >= 3 non-collinear points (>= 2 with
// `with_scale = false` and a unique solution otherwise nullopt).
std::optional<Sim3d> AlignSim3(const std::vector<Eigen::Vector3d>& source,
                               const std::vector<Eigen::Vector3d>& target, bool with_scale = true);

}  // namespace uwscan
