#include "uwscan/calib/synthetic_views.h"

#include <cmath>
#include <random>

#include "uwscan/util/error.h"

namespace uwscan {

void SyntheticViewOptions::Check() const {
  UWS_CHECK(num_views >= 1, "num_views must be >= 1");
  UWS_CHECK(min_range_m > 0.0 && max_range_m >= min_range_m, "bad range band [", min_range_m, ", ",
            max_range_m, "]");
  UWS_CHECK(noise_px >= 0.0, "noise must be >= 0");
}

bool ProjectBoard(const Camera& camera, const BoardSpec& board, const Rigid3d& camera_from_board,
                  double margin_px, std::vector<Eigen::Vector2d>* corners) {
  corners->clear();
  for (const Eigen::Vector3d& point : board.Corners()) {
    const auto pixel = camera.Project(camera_from_board * point, ProjectionMethod::kExact);
    if (!pixel || !camera.InImage(*pixel, margin_px)) return false;
    corners->push_back(*pixel);
  }
  return true;
}

CornerSet SyntheticCornerSet(const Camera& truth, const BoardSpec& board,
                             const SyntheticViewOptions& options,
                             std::vector<Rigid3d>* camera_from_board) {
  options.Check();
  std::mt19937 rng(options.seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, options.noise_px);
  CornerSet set;
  set.board = board;
  set.width = truth.width;
  set.height = truth.height;
  if (camera_from_board) camera_from_board->clear();
  const Eigen::Vector3d centre((board.cols - 1) * board.square_m / 2.0,
                               (board.rows - 1) * board.square_m / 2.0, 0.0);
  int tries = 0;
  while (static_cast<int>(set.views.size()) < options.num_views) {
    UWS_CHECK(++tries < 2000 * options.num_views,
              "synthetic views: no board pose fits the image in the range band");
    // Board centre on the pinhole ray of a random pixel.
    const double u = truth.width * (0.15 + 0.7 * uniform(rng));
    const double v = truth.height * (0.15 + 0.7 * uniform(rng));
    const Eigen::Vector3d ray((u - truth.intrinsics[2]) / truth.intrinsics[0],
                              (v - truth.intrinsics[3]) / truth.intrinsics[1], 1.0);
    const double range =
        options.min_range_m + (options.max_range_m - options.min_range_m) * uniform(rng);
    const Eigen::Vector3d position = ray.normalized() * range;
    // Tilt about a random axis in the board plane, plus a spin about its normal.
    const double tilt = options.max_tilt_deg * M_PI / 180.0 * std::sqrt(uniform(rng));
    const double axis_angle = 2.0 * M_PI * uniform(rng);
    const double spin = (uniform(rng) - 0.5) * 0.5;
    const Eigen::Quaterniond rotation =
        Eigen::Quaterniond(Eigen::AngleAxisd(
            tilt, Eigen::Vector3d(std::cos(axis_angle), std::sin(axis_angle), 0.0))) *
        Eigen::Quaterniond(Eigen::AngleAxisd(spin, Eigen::Vector3d::UnitZ()));
    const Rigid3d pose(rotation, position - rotation * centre);
    std::vector<Eigen::Vector2d> corners;
    if (!ProjectBoard(truth, board, pose, options.margin_px, &corners)) continue;
    for (Eigen::Vector2d& c : corners) c += Eigen::Vector2d(noise(rng), noise(rng));
    set.views.push_back({"view" + std::to_string(set.views.size()), corners});
    if (camera_from_board) camera_from_board->push_back(pose);
  }
  return set;
}

Camera AquariumTestCamera(double d_air_m, double tilt_deg) {
  Camera camera;
  camera.name = "cam0";
  camera.width = 1280;
  camera.height = 960;
  camera.model = CameraModelId::kFlatPort;
  camera.intrinsics = {1112.70, 1112.58, 625.64, 443.93};
  camera.distortion = {-0.0489, 0.1037, 0.0005, -0.0003, 0.0};
  const double tilt = tilt_deg * M_PI / 180.0;
  camera.port.normal = Eigen::Vector3d(std::sin(tilt), 0.0, std::cos(tilt));
  camera.port.d_air = d_air_m;
  camera.port.d_glass = 0.006;
  camera.port.n_air = 1.0;
  camera.port.n_glass = 1.52;
  camera.port.n_water = 1.333;
  return camera;
}

}  // namespace uwscan
