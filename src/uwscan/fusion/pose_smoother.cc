#include "uwscan/fusion/pose_smoother.h"

#include <Eigen/Dense>
#include <Eigen/Geometry>

namespace uwscan::fusion {
namespace {

Eigen::Vector3d Log(const Eigen::Quaterniond& q) {
  const Eigen::AngleAxisd aa(q.normalized());
  return aa.angle() * aa.axis();
}

Eigen::Quaterniond Exp(const Eigen::Vector3d& v) {
  const double angle = v.norm();
  if (angle < 1e-15) return Eigen::Quaterniond::Identity();
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, v / angle));
}

}  // namespace

PoseUpdate PoseSmoother::Smooth(size_t index) const {
  const Entry& centre = buffer_[index];
  const size_t first = index >= static_cast<size_t>(half_window_) ? index - half_window_ : 0;
  const size_t last = std::min(buffer_.size() - 1, index + half_window_);
  const int n = static_cast<int>(last - first + 1);
  if (n < 5) return centre.pose;  // too few for a quadratic with noise to spare
  Eigen::MatrixXd design(n, 3);
  Eigen::MatrixXd values(n, 6);
  const Eigen::Quaterniond inverse = centre.pose.world_from_camera.rotation.conjugate();
  for (int k = 0; k < n; ++k) {
    const Entry& e = buffer_[first + k];
    const double dt = e.timestamp_s - centre.timestamp_s;
    design.row(k) << 1.0, dt, dt * dt;
    values.block<1, 3>(k, 0) = e.pose.world_from_camera.translation.transpose();
    values.block<1, 3>(k, 3) = Log(inverse * e.pose.world_from_camera.rotation).transpose();
  }
  const Eigen::MatrixXd coefficients = design.colPivHouseholderQr().solve(values);
  PoseUpdate smoothed = centre.pose;
  smoothed.world_from_camera.translation = coefficients.block<1, 3>(0, 0).transpose();
  smoothed.world_from_camera.rotation =
      (centre.pose.world_from_camera.rotation * Exp(coefficients.block<1, 3>(0, 3).transpose()))
          .normalized();
  return smoothed;
}

std::vector<PoseUpdate> PoseSmoother::Add(const PoseUpdate& pose, double timestamp_s) {
  if (half_window_ <= 0) return {pose};
  buffer_.push_back({pose, timestamp_s});
  std::vector<PoseUpdate> out;
  // An entry is final once half_window poses follow it.
  while (emitted_ + half_window_ < buffer_.size()) {
    out.push_back(Smooth(emitted_));
    ++emitted_;
  }
  // Keep only what later windows still need.
  while (emitted_ > static_cast<size_t>(half_window_)) {
    buffer_.pop_front();
    --emitted_;
  }
  return out;
}

std::vector<PoseUpdate> PoseSmoother::Flush() {
  std::vector<PoseUpdate> out;
  for (; emitted_ < buffer_.size(); ++emitted_) out.push_back(Smooth(emitted_));
  buffer_.clear();
  emitted_ = 0;
  return out;
}

}  // namespace uwscan::fusion
