#include "uwscan/pipeline/track_accuracy_benchmark.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "uwscan/fusion/self_referenced.h"
#include "uwscan/io/tum.h"
#include "uwscan/laser/detector.h"
#include "uwscan/pipeline/laser_detect.h"
#include "uwscan/pipeline/vo_dataset.h"
#include "uwscan/sim/scene_yaml.h"
#include "uwscan/util/error.h"
#include "uwscan/util/statistics.h"
#include "uwscan/vo/feature_tracker.h"

namespace fs = std::filesystem;

namespace uwscan {
namespace {

// Least-squares gain of tracked over true displacement, per axis.
struct GainSums {
  double error_dot_true[2] = {0.0, 0.0};
  double true_squared[2] = {0.0, 0.0};
  long samples = 0;
  void Add(const Eigen::Vector2d& error, const Eigen::Vector2d& displacement) {
    for (int a = 0; a < 2; ++a) {
      error_dot_true[a] += error[a] * displacement[a];
      true_squared[a] += displacement[a] * displacement[a];
    }
    ++samples;
  }
  TrackAccuracyResult::Gain Gain() const {
    const auto ratio = [](double num, double den) { return den > 0.0 ? num / den : 0.0; };
    const auto rms = [this](double sum) { return samples > 0 ? std::sqrt(sum / samples) : 0.0; };
    return {ratio(error_dot_true[0], true_squared[0]), ratio(error_dot_true[1], true_squared[1]),
            rms(true_squared[0]), rms(true_squared[1]), samples};
  }
};

double Percentile(std::vector<double> values, double fraction) {
  if (values.empty()) return 0.0;
  const size_t k = std::min(values.size() - 1, static_cast<size_t>(fraction * values.size()));
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return values[k];
}

}  // namespace

void TrackAccuracyOptions::Check() const {
  UWS_USAGE_CHECK(!dataset.empty(), "bench tracks: --dataset is required");
  UWS_USAGE_CHECK(frames >= 0, "bench tracks: --frames must be >= 0, got ", frames);
  UWS_USAGE_CHECK(anchor_every >= 1, "bench tracks: --anchor-every must be >= 1, got ",
                  anchor_every);
  UWS_USAGE_CHECK(contrast_scale >= 0.0 && contrast_scale <= 0.5,
                  "bench tracks: --contrast-scale must be in [0, 0.5], got ", contrast_scale);
  UWS_USAGE_CHECK(lost_px > 0.0, "bench tracks: lost_px must be > 0");
}

nlohmann::json TrackAccuracyResult::ToJson() const {
  const auto gain = [](const Gain& g) {
    return nlohmann::json{{"x_percent", 100.0 * g.x},
                          {"y_percent", 100.0 * g.y},
                          {"motion_x_px", g.motion_x_px},
                          {"motion_y_px", g.motion_y_px},
                          {"samples", g.samples}};
  };
  return {
      {"benchmark", "tracks"},
      {"frames", frames},
      {"samples", samples},
      {"lost", lost},
      {"flow_gain_minus_1", {{"all", gain(all)}, {"centre", gain(centre)}, {"edges", gain(edges)}}},
      {"median_error_px", median_error_px},
      {"p95_error_px", p95_error_px}};
}

TrackAccuracyResult RunTrackAccuracyBenchmark(const TrackAccuracyOptions& options) {
  options.Check();
  UWS_CHECK(fs::is_directory(options.dataset), options.dataset.string(),
            ": no such dataset folder");
  const fs::path scene_file = options.dataset / "scene.yaml";
  const fs::path truth_file = options.dataset / "groundtruth.tum";
  UWS_CHECK(fs::exists(scene_file), scene_file.string(),
            ": missing: bench tracks needs a simulated dataset with its scene");
  UWS_CHECK(fs::exists(truth_file), truth_file.string(),
            ": missing: bench tracks needs the true trajectory");
  const VoDataset dataset = ReadVoDataset(options.dataset);
  UWS_CHECK(!dataset.rig.lasers.empty(), (options.dataset / "rig.yaml").string(),
            ": no laser (bench tracks masks the line as the scan does)");
  sim::Scenario scenario = sim::LoadDatasetScenario(options.dataset);
  scenario.config.scene.Prepare();
  const std::vector<StampedPose> truth = ReadTum(truth_file);

  const Camera& camera = dataset.rig.cameras.front();
  laser::DetectorOptions detector;
  detector.laser_channel = laser::ChannelForWavelength(dataset.rig.lasers[0].wavelength_nm);
  detector.scan_rows = LaserLineIsVertical(camera, dataset.rig.CameraFromLaser(0, 0));
  fusion::SelfReferencedOptions provider_options;
  provider_options.contrast_sigma_fraction = options.contrast_scale;
  const fusion::SelfReferencedPoseProvider provider(camera, detector.laser_channel,
                                                    provider_options);
  vo::FeatureTracker tracker(provider_options.odometry.tracker);

  struct Start {
    Eigen::Vector3d point_world;
    Eigen::Vector2d pixel;
  };
  std::unordered_map<uint64_t, Start> starts;
  GainSums all, centre, edges;
  std::vector<double> errors;
  TrackAccuracyResult result;
  const int frames = options.frames > 0
                         ? std::min<int>(options.frames, static_cast<int>(dataset.frames.size()))
                         : static_cast<int>(dataset.frames.size());
  for (int i = 0; i < frames; ++i) {
    const FrameRecord& entry = dataset.frames[static_cast<size_t>(i)];
    const cv::Mat raw = ReadFrameImage(dataset, entry);
    UWS_CHECK(!raw.empty() && raw.cols == camera.width && raw.rows == camera.height,
              (options.dataset / entry.file).string(), ": unreadable or not ", camera.width, "x",
              camera.height);
    const laser::Detection detection =
        laser::DetectLaserLine(raw, laser::LayoutFor(camera.bayer, raw.channels()), detector);
    fusion::FrameInput input;
    input.index = entry.index;
    input.timestamp_s = entry.timestamp_s;
    input.image = raw;
    input.detection = &detection;
    const fusion::PreparedFrame prepared = provider.PrepareAhead(input);
    const Camera tracked = provider.TrackedCamera(raw);
    tracker.Track(prepared.image, prepared.mask);
    if (i % options.anchor_every == 0) {
      tracker.Detect(prepared.mask);
      // As the odometry's keyframes on a hover (made for time, not
      // parallax): tracks keep their first anchors (anchor_keep_keyframes).
      tracker.SetAnchor(prepared.mask, /*view_moved=*/false);
    }
    const std::optional<Rigid3d> pose = fusion::InterpolatePose(truth, entry.timestamp_s, 1e-3);
    UWS_CHECK(pose.has_value(), truth_file.string(), ": no pose at ", entry.timestamp_s,
              " s (frame ", entry.index, ")");
    const Rigid3d camera_from_world = pose->Inverse();
    const Eigen::Vector2d half_size(tracked.width / 2.0, tracked.height / 2.0);
    for (const vo::FeatureTrack& track : tracker.tracks()) {
      const auto start = starts.find(track.id);
      if (start == starts.end()) {
        const std::optional<Ray> ray = tracked.BackProject(track.pixel);
        if (!ray) continue;
        const Ray world = ray->Transformed(*pose);
        const auto hit = scenario.config.scene.Intersect(world.origin, world.direction);
        if (hit) starts.emplace(track.id, Start{hit->point_world, track.pixel});
        continue;
      }
      const std::optional<Eigen::Vector2d> truth_pixel =
          tracked.Project(camera_from_world * start->second.point_world);
      if (!truth_pixel) continue;
      ++result.samples;
      const Eigen::Vector2d error = track.pixel - *truth_pixel;
      if (error.norm() > options.lost_px) {
        ++result.lost;
        continue;
      }
      errors.push_back(error.norm());
      const Eigen::Vector2d displacement = *truth_pixel - start->second.pixel;
      const Eigen::Vector2d relative =
          (track.pixel - half_size).cwiseQuotient(half_size).cwiseAbs();
      all.Add(error, displacement);
      (relative.maxCoeff() < 0.5 ? centre : edges).Add(error, displacement);
    }
  }
  result.frames = frames;
  result.all = all.Gain();
  result.centre = centre.Gain();
  result.edges = edges.Gain();
  result.median_error_px = Median(errors);
  result.p95_error_px = Percentile(errors, 0.95);
  return result;
}

}  // namespace uwscan
