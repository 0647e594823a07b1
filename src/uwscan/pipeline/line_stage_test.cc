// The line stage inside `reconstruct`, end to end on simulated scans: what
// the detector leaves out (albedo edges, painted stripes, particles lit by
// the floods) and how it is found (difference images, the servo sweep's and
// the moving platform's filters).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "uwscan/io/image.h"
#include "uwscan/io/rig_yaml.h"
#include "uwscan/pipeline/evaluate_reconstruction.h"
#include "uwscan/pipeline/laser_detect.h"
#include "uwscan/pipeline/reconstruct.h"
#include "uwscan/pipeline/testing.h"
#include "uwscan/util/atomic_file.h"
#include "uwscan/util/error.h"

namespace uwscan {
namespace {
namespace fs = std::filesystem;
using namespace pipeline_testing;

// A tank-target scan at 480x360 with a white stripe painted beside the
// target, simulated into root/data, and a job placing it with the true poses.
ReconstructJob StripeScanWithTruePoses(const fs::path& root, int frames, uint64_t seed,
                                       bool interleave) {
  sim::ScenarioOptions options = ScanOptions(480, 360, frames, seed);
  options.painted_stripe_m = 0.02;
  options.painted_stripe_colour = "white";
  options.laser_interleave = interleave;
  return SimulatedJobOnTruePoses(root, "tank-target", options);
}

// Where the line runs along a square's side of the checkerboard the edge
// pulls the line towards the white square, by up to a pixel: several mm at
// 2 m. Dropping those points (judged in the red LED's channel) leaves a
// flatter target. At the thesis camera's 1280x960, where the line is wide
// enough in pixels for the bias to dominate; 16 frames cross the target.
TEST(ReconstructAlbedoEdges, PointsOnTheTargetsSquareEdgesAreDropped) {
  const fs::path root = TempFolder("albedo_edges");
  sim::ScenarioOptions options;
  options.frames = 16;
  options.seed = 21;
  ReconstructJob job = SimulatedJobOnTruePoses(root, "tank-target", options);
  job.out = root / "kept";
  job.drop_albedo_edges = false;
  const ReconstructReport kept = RunReconstruct(job);
  EXPECT_EQ(kept.albedo_edge_points, 0);
  const SurfaceAccuracy kept_board =
      *EvaluateReconstruction(job.dataset, job.out).compensated.Surface("checkerboard");
  job.out = root / "dropped";
  job.drop_albedo_edges = true;
  const ReconstructReport dropped = RunReconstruct(job);
  const SurfaceAccuracy dropped_board =
      *EvaluateReconstruction(job.dataset, job.out).compensated.Surface("checkerboard");
  std::printf("target: %ld points, plane std %.3f mm kept; %ld points, %.3f mm dropped\n",
              kept_board.points, kept_board.fit_rms_m * 1e3, dropped_board.points,
              dropped_board.fit_rms_m * 1e3);
  EXPECT_GT(dropped.albedo_edge_points, 0);
  EXPECT_EQ(dropped.points + dropped.albedo_edge_points, kept.points);
  EXPECT_GT(kept_board.points, 500);
  EXPECT_GT(dropped_board.points, kept_board.points / 2);
  EXPECT_LT(dropped_board.fit_rms_m, 0.5 * kept_board.fit_rms_m);
  EXPECT_LT(dropped_board.fit_rms_m, 0.001);
  fs::remove_all(root);
}

// Thesis §5.4: with the laser on in every other frame the line is found in
// the difference to the laser-off frame before, where a white stripe painted
// beside the target (bright in every colour, taken for the line in a single
// frame) cancels; the laser-off frames carry no line and no mask.
TEST(ReconstructInterleaved, DifferenceImagesIgnoreAPaintedStripe) {
  const fs::path root = TempFolder("interleaved");
  ReconstructJob job = StripeScanWithTruePoses(root, 24, 23, /*interleave=*/true);
  job.out = root / "difference";
  const ReconstructReport report = RunReconstruct(job);
  EXPECT_EQ(report.frames_laser_off, 12);
  EXPECT_EQ(report.frames_on_difference, 11);  // the first frame has no laser-off frame before
  EXPECT_EQ(report.frames_with_line, 11);
  EXPECT_GT(report.points, 11 * 150);
  // At most the note that static candidates (the target's edges, which
  // moved a little between the two frames) were ignored, and that the red
  // clips (at 480x360 a pixel gathers 7 times the light of the thesis
  // camera's, and the stripe is white).
  for (const std::string& warning : report.Warnings()) {
    EXPECT_TRUE(warning.find("stayed put") != std::string::npos ||
                warning.find("the features' colour (red, lit by the floods)") != std::string::npos)
        << warning;
  }
  const auto with_difference = EvaluateReconstruction(job.dataset, job.out);
  EXPECT_LT(with_difference.compensated.point_error_rms_m, 0.003);

  job.out = root / "single";
  job.detect_on_difference = false;
  job.texture_filter = false;
  RunReconstruct(job);
  const auto single = EvaluateReconstruction(job.dataset, job.out);
  EXPECT_GT(single.compensated.point_error_rms_m, 0.05);  // the stripe, triangulated

  // frames.csv's laser_on the wrong way round: hardly a line in a difference,
  // and the warning names the column (the right one above did not).
  EXPECT_EQ(report.laser_on_inverted_at, -1);
  std::string csv = FileBytes(job.dataset / "frames.csv"), flipped;
  for (size_t at = 0, end; at < csv.size(); at = end + 1) {
    end = std::min(csv.find('\n', at), csv.size());
    std::string line = csv.substr(at, end - at);
    if (at > 0 && !line.empty()) line.back() = line.back() == '1' ? '0' : '1';
    flipped += line + "\n";
  }
  WriteFileAtomic(job.dataset / "frames.csv", flipped);
  job.out = root / "flipped";
  job.detect_on_difference = true;
  job.texture_filter = true;
  const ReconstructReport inverted = RunReconstruct(job);
  EXPECT_LE(inverted.frames_with_line, 2);  // of 12 marked on
  EXPECT_EQ(inverted.laser_on_inverted_at, 2);
  ASSERT_FALSE(inverted.Warnings().empty());
  EXPECT_EQ(inverted.Warnings().front().find("frames.csv's laser_on column looks inverted: frame "
                                             "2, marked laser off, shows the line"),
            0u)
      << inverted.Warnings().front();
  fs::remove_all(root);
}

// Thesis §5.5 on a servo scan without interleaving: the white stripe's
// candidates stay put while the sheet sweeps and are ignored before the
// detector picks one peak per scan line, so the laser is found where the
// stripe outshone it; without the filter the stripe is triangulated.
TEST(ReconstructSweepFilter, StaticCandidatesOfAPaintedStripeAreIgnored) {
  const fs::path root = TempFolder("sweep_filter");
  ReconstructJob job = StripeScanWithTruePoses(root, 40, 29, /*interleave=*/false);
  job.out = root / "filtered";
  const ReconstructReport report = RunReconstruct(job);
  EXPECT_GT(report.frames_with_static_detections, 20);
  EXPECT_TRUE(Warns(report, {"stayed put"}));
  const auto filtered = EvaluateReconstruction(job.dataset, job.out);
  EXPECT_LT(filtered.compensated.point_error_rms_m, 0.003);
  EXPECT_GT(report.points, 40 * 150);

  job.out = root / "unfiltered";
  job.texture_filter = false;
  RunReconstruct(job);
  const auto unfiltered = EvaluateReconstruction(job.dataset, job.out);
  EXPECT_GT(unfiltered.compensated.point_error_rms_m, 0.05);
  fs::remove_all(root);
}

// Marine snow (two particles per litre) near the red LEDs: the nearest
// particles are lit so brightly that red clips and green shows them through
// the filters' crosstalk, as bright as the line; where the line is faint
// they took its scan lines and were triangulated metres behind the floor.
// They have none of the 532 nm line's blue and are ignored, and the report
// says so; with --keep-off-colour they are back. (Those whose ray grazes
// the light sheet, the farthest, go without the colour test too.)
TEST(ReconstructMarineSnow, FloodLitParticlesAreNotTakenForTheLine) {
  const fs::path root = TempFolder("marine_snow");
  sim::ScenarioOptions options = ScanOptions(480, 360, 40, 311);
  options.marine_snow_per_m3 = 2000;
  ReconstructJob job = SimulatedJobOnTruePoses(root, "tank-target", options);
  job.out = root / "dropped";
  const ReconstructReport dropped = RunReconstruct(job);
  EXPECT_GT(dropped.off_colour_points, 50);
  EXPECT_GT(dropped.frames_with_off_colour, 5);
  EXPECT_TRUE(Warns(dropped, {"colour signature"}));
  const auto clean = EvaluateReconstruction(job.dataset, job.out);
  EXPECT_GT(dropped.points, 40 * 60);
  EXPECT_LT(clean.compensated.point_error_rms_m, 0.01);

  job.out = root / "kept";
  job.drop_off_colour = false;
  job.max_range_error_per_px = 0.0;
  const ReconstructReport kept = RunReconstruct(job);
  EXPECT_EQ(kept.off_colour_points, 0);
  EXPECT_EQ(kept.grazing_points, 0);
  const auto snowy = EvaluateReconstruction(job.dataset, job.out);
  EXPECT_GT(snowy.compensated.point_error_rms_m, 0.5);  // particles metres off the floor

  job.out = root / "grazing";
  job.max_range_error_per_px = laser::kMaxRangeErrorPerPixel;
  const ReconstructReport grazing = RunReconstruct(job);
  EXPECT_GT(grazing.grazing_points, 0);
  EXPECT_EQ(kept.points - grazing.points, grazing.grazing_points);  // only they went
  const auto nearer = EvaluateReconstruction(job.dataset, job.out);
  // The gate takes out the farthest particles (725 -> 502 mm). Until the
  // simulator stopped imaging particles from past the lens's fold (more
  // than 45 degrees off the axis in water), a few of those, wrongly
  // placed in the image, had made it 11.7 m -> 0.38 m.
  EXPECT_LT(nearer.compensated.point_error_rms_m, snowy.compensated.point_error_rms_m);
  EXPECT_GT(nearer.compensated.point_error_rms_m, 10 * clean.compensated.point_error_rms_m);
  std::printf(
      "marine snow: point error %.1f mm with the colour test, %.0f mm without, %.0f mm without "
      "but with the grazing rays dropped (%ld points)\n",
      clean.compensated.point_error_rms_m * 1e3, snowy.compensated.point_error_rms_m * 1e3,
      nearer.compensated.point_error_rms_m * 1e3, grazing.grazing_points);
  fs::remove_all(root);
}

// A fixed laser on a moving platform (seabed-transect): stripes painted
// across the track pass through the laser's line as the vehicle moves, and
// win scan lines from it; they move with the scene, the line does not
// (thesis §5.5): the motion filter leaves them out and the floor is right.
TEST(ReconstructMotionFilter, StripesMovingWithTheSceneAreIgnored) {
  const fs::path root = TempFolder("motion_filter");
  sim::ScenarioOptions options = ScanOptions(640, 480, 40, 1);
  options.painted_stripe_m = 0.02;
  ReconstructJob job = SimulatedJobOnTruePoses(root, "seabed-transect", options);
  job.out = root / "filtered";
  const ReconstructReport filtered = RunReconstruct(job);
  job.out = root / "kept";
  job.texture_filter = false;
  const ReconstructReport kept = RunReconstruct(job);
  const SurfaceAccuracy with_filter =
      *EvaluateReconstruction(job.dataset, root / "filtered").compensated.Surface("floor");
  const SurfaceAccuracy without =
      *EvaluateReconstruction(job.dataset, root / "kept").compensated.Surface("floor");
  std::printf("floor point error: %.2f mm filtered (%ld candidates ignored), %.2f mm kept\n",
              with_filter.point_error_rms_m * 1e3, filtered.static_detections_removed,
              without.point_error_rms_m * 1e3);
  EXPECT_EQ(kept.static_detections_removed, 0);
  EXPECT_GT(filtered.static_detections_removed, 100);
  EXPECT_GT(without.point_error_rms_m, 0.02);
  EXPECT_LT(with_filter.point_error_rms_m, 0.003);
  EXPECT_GT(filtered.points, kept.points * 9 / 10);
  fs::remove_all(root);
}

// A 12-bit camera's frames saved unpacked: the samples in the low bits of
// 16-bit PNGs, 16 times darker than the simulator's 12-bit frames (scaled to
// the full range). Read as stored, a warning names the first frame and the
// option; with --sample-bits 12 the clouds are byte for byte the full-range
// frames' clouds. The line with the true poses, 320x240 (gain 1: the
// scene's exposure at this size).
TEST(ReconstructSampleBits, TwelveBitFramesSavedUnpackedAreScaledUp) {
  const fs::path root = TempFolder("sample_bits");
  sim::ScenarioOptions options = ScanOptions(320, 240, 12, 5);
  options.bits = 12;
  options.gain = 1.0;
  ReconstructJob job = SimulatedJobOnTruePoses(root, "tank-target", options);
  job.out = root / "full_range";
  const ReconstructReport full_range = RunReconstruct(job);
  EXPECT_EQ(full_range.first_frame.low_sample_bits, 0);
  EXPECT_GT(full_range.points, 12 * 50);

  for (const auto& entry : fs::directory_iterator(job.dataset / "frames")) {
    const cv::Mat stored = ReadImage(entry.path());
    ASSERT_EQ(stored.depth(), CV_16U);
    WritePng(entry.path(), stored / 16);
  }
  job.out = root / "as_stored";
  const ReconstructReport as_stored = RunReconstruct(job);
  EXPECT_EQ(as_stored.first_frame.file, job.dataset / "frames/000000.png");
  EXPECT_EQ(as_stored.first_frame.low_sample_bits, 12);
  EXPECT_TRUE(Warns(as_stored, {"give --sample-bits 12"}));

  job.out = root / "scaled";
  job.sample_bits = 12;
  const ReconstructReport scaled = RunReconstruct(job);
  EXPECT_EQ(scaled.first_frame.low_sample_bits, 0);
  EXPECT_EQ(scaled.points, full_range.points);
  EXPECT_EQ(FileBytes(root / "scaled/cloud.ply"), FileBytes(root / "full_range/cloud.ply"));

  // A sample beyond 12 bits is not a 12-bit camera's: named.
  cv::Mat frame = ReadImage(job.dataset / "frames/000003.png");
  frame.at<uint16_t>(7, 9) = 4096;
  WritePng(job.dataset / "frames/000003.png", frame);
  job.out = root / "beyond";
  try {
    RunReconstruct(job);
    ADD_FAILURE() << "a 13-bit sample was taken";
  } catch (const Error& e) {
    EXPECT_NE(
        std::string(e.what()).find("frames/000003.png: a sample of 4096 does not fit 12 bits"),
        std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(fs::exists(root / "beyond"));
  fs::remove_all(root);
}

// A laser pose written the wrong way round in rig.yaml (laser_from_camera
// as camera_from_laser): most line points meet the light sheet nowhere in
// front of the camera, and the report says the inverse would place them.
TEST(ReconstructLaserPose, AnInvertedLaserPoseIsNamed) {
  const fs::path root = TempFolder("inverted_laser");
  ReconstructJob job = SimulatedJobOnTruePoses(root, "tank-target", ScanOptions(320, 240, 6, 31));
  job.out = root / "right";
  const ReconstructReport right = RunReconstruct(job);
  EXPECT_EQ(right.triangulation_failures, 0);
  EXPECT_FALSE(right.laser_pose_inverse_fits);
  EXPECT_GT(right.points, 6 * 30);

  Rig rig = ReadRigYaml(job.dataset / "rig.yaml");
  rig.lasers.front().camera_from_laser = rig.lasers.front().camera_from_laser.Inverse();
  WriteRigYaml(job.dataset / "rig.yaml", rig);
  job.out = root / "inverted";
  const ReconstructReport inverted = RunReconstruct(job);
  EXPECT_TRUE(inverted.laser_pose_inverse_fits);
  EXPECT_GT(inverted.triangulation_failures, right.points / 4);
  const std::vector<std::string> warnings = inverted.Warnings();
  EXPECT_TRUE(std::any_of(warnings.begin(), warnings.end(), [](const std::string& w) {
    return w.find(
               "met the laser's light sheet nowhere in front of the camera and are left out: "
               "the laser's pose in rig.yaml looks inverted") != std::string::npos;
  })) << (warnings.empty() ? "no warning" : warnings.front());

  // `laser detect --profiles` finds the same.
  LaserDetectJob detect;
  detect.dataset_dir = job.dataset;
  detect.detections_csv = root / "detections.csv";
  detect.profiles_csv = root / "profiles.csv";
  detect.quiet = true;
  const LaserDetectSummary detected = RunLaserDetect(detect);
  EXPECT_TRUE(detected.laser_pose_inverse_fits);
  EXPECT_GT(detected.missed_points, right.points / 4);
  fs::remove_all(root);
}

// A red laser's line with rig.yaml's wavelength_nm left at a green one's:
// the detector finds hardly a line in green, and the report names the
// colour it shows in. The simulator's RGB frames with red and green
// swapped stand for it.
TEST(ReconstructLaserColour, ALineInAnotherColourIsNamed) {
  const fs::path root = TempFolder("laser_colour");
  sim::ScenarioOptions options = ScanOptions(320, 240, 4, 37);
  options.output = sim::OutputFormat::kRgb;
  ReconstructJob job = SimulatedJobOnTruePoses(root, "tank-target", options);
  job.out = root / "green";
  const ReconstructReport green = RunReconstruct(job);
  EXPECT_EQ(green.laser_seen_in, "");
  EXPECT_EQ(green.frames_with_line, 4);

  for (const auto& entry : fs::directory_iterator(job.dataset / "frames")) {
    std::vector<cv::Mat> bgr;
    cv::split(ReadImage(entry.path()), bgr);
    std::swap(bgr[1], bgr[2]);
    cv::Mat swapped;
    cv::merge(bgr, swapped);
    WritePng(entry.path(), swapped);
  }
  job.out = root / "red";
  const ReconstructReport red = RunReconstruct(job);
  EXPECT_EQ(red.laser_seen_in, "red");
  ASSERT_FALSE(red.Warnings().empty());
  EXPECT_EQ(red.Warnings().front().find("the laser line shows in red, not in green, the colour of "
                                        "its 532 nm in rig.yaml"),
            0u)
      << red.Warnings().front();
  fs::remove_all(root);
}

}  // namespace
}  // namespace uwscan
