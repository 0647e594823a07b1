#include "uwscan/fusion/self_referenced.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "uwscan/pipeline/evaluate_reconstruction.h"
#include "uwscan/pipeline/reconstruct.h"
#include "uwscan/sim/simulate.h"

namespace uwscan::fusion {
namespace {
namespace fs = std::filesystem;

// End to end on a short simulated hover over the tank target: the
// self-referenced poses must place the laser profiles clearly better than no
// compensation, checked against the simulator's truth.
// Also with the odometry on a half-size image (the path taken at
// 1280x960 by default): the red samples of the raw mosaic at half size.
class SelfReferencedHover : public ::testing::TestWithParam<int> {};

TEST_P(SelfReferencedHover, CompensatesHoverMotion) {
  const fs::path root = fs::temp_directory_path() /
                        ("uwscan_fusion_test_" + std::to_string(::getpid()) + "_" +
                         std::to_string(GetParam()));
  fs::remove_all(root);
  sim::ScenarioOptions options;
  options.width = 480;
  options.height = 360;
  options.frames = 90;
  options.seed = 4;
  sim::SimulateScenario("tank-target", options, root / "data");
  ReconstructJob job;
  job.dataset = root / "data";
  job.out = root / "out";
  job.quiet = true;
  job.self_referenced.max_tracking_width = GetParam();
  const ReconstructReport report = RunReconstruct(job);
  EXPECT_EQ(report.pose_details["tracked_image_width"].get<int>(),
            GetParam() == 0 ? 480 : GetParam());
  EXPECT_EQ(report.pose_source, "self-referenced visual odometry");
  EXPECT_LT(report.frames_without_pose, 20);
  const auto evaluation = EvaluateReconstruction(job.dataset, job.out);
  const double compensated = evaluation.compensated.point_error_rms_m;
  const double uncompensated = evaluation.uncompensated.point_error_rms_m;
  EXPECT_LT(compensated, 0.5 * uncompensated) << compensated << " vs " << uncompensated;
  const SurfaceAccuracy* floor_c = evaluation.compensated.Surface("floor");
  const SurfaceAccuracy* floor_u = evaluation.uncompensated.Surface("floor");
  ASSERT_TRUE(floor_c && floor_u);
  EXPECT_LT(floor_c->distance_error_mean_pct, 0.5 * floor_u->distance_error_mean_pct);
  fs::remove_all(root);
}

INSTANTIATE_TEST_SUITE_P(TrackedWidth, SelfReferencedHover, ::testing::Values(0, 240));

TEST(SelfReferenced, BayerSamplesOfTheLedColour) {
  using P = SelfReferencedPoseProvider;
  EXPECT_EQ(P::BayerSampleOffset("rggb", laser::kRed), cv::Point(0, 0));
  EXPECT_EQ(P::BayerSampleOffset("bggr", laser::kRed), cv::Point(1, 1));
  EXPECT_EQ(P::BayerSampleOffset("grbg", laser::kRed), cv::Point(1, 0));
  EXPECT_EQ(P::BayerSampleOffset("gbrg", laser::kRed), cv::Point(0, 1));
  EXPECT_EQ(P::BayerSampleOffset("rggb", laser::kBlue), cv::Point(1, 1));
  EXPECT_FALSE(P::BayerSampleOffset("rggb", laser::kGreen).has_value());
  EXPECT_FALSE(P::BayerSampleOffset("none", laser::kRed).has_value());
  cv::Mat mosaic(4, 6, CV_16U);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 6; ++c) mosaic.at<uint16_t>(r, c) = static_cast<uint16_t>(100 * r + c);
  const cv::Mat red = P::BayerChannel(mosaic, cv::Point(1, 0));  // grbg
  ASSERT_EQ(red.size(), cv::Size(3, 2));
  EXPECT_EQ(red.at<uint16_t>(1, 2), 100 * 2 + 5);
}

TEST(SelfReferenced, PassiveImageAvoidsTheLaserColour) {
  // A raw RGGB mosaic: red pixels 200, the rest 10.
  cv::Mat mosaic(8, 8, CV_8U, cv::Scalar(10));
  for (int r = 0; r < 8; r += 2) {
    for (int c = 0; c < 8; c += 2) mosaic.at<uint8_t>(r, c) = 200;
  }
  const cv::Mat red = SelfReferencedPoseProvider::PassiveImage(mosaic, "rggb", laser::kGreen);
  ASSERT_EQ(red.channels(), 1);
  EXPECT_GT(cv::mean(red)[0], 150.0);
  const cv::Mat mono(8, 8, CV_8U, cv::Scalar(5));
  EXPECT_EQ(SelfReferencedPoseProvider::PassiveImage(mono, "none", laser::kGreen).data, mono.data);
  // A smooth shading ramp vanishes under the illumination normalisation.
  cv::Mat ramp(64, 64, CV_8U);
  for (int r = 0; r < 64; ++r) ramp.row(r).setTo(cv::Scalar(50 + 2 * r));
  const cv::Mat flat = SelfReferencedPoseProvider::NormalizeIllumination(ramp, 6.0);
  cv::Scalar mean, stddev;
  cv::meanStdDev(flat(cv::Rect(16, 16, 32, 32)), mean, stddev);
  EXPECT_NEAR(mean[0], 128.0, 2.0);
  EXPECT_LT(stddev[0], 2.0);
}

}  // namespace
}  // namespace uwscan::fusion
