// The figures of docs/simulator.md: the tank-target scene in clear, coastal
// and turbid water (image strip), the mean laser-line profile across the
// line (plot), and one frame of every scenario. Written when
// UWSCAN_FIGURE_DIR is set:
//   UWSCAN_FIGURE_DIR=docs/img build/tests/sim_figures_test
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "uwscan/sim/scenario.h"
#include "uwscan/sim/testing.h"

namespace uwscan::sim {
namespace {

// Presets and one level between coastal and turbid (c_p(530) = 1 /m).
const std::vector<std::string> kWaters = {"clear", "coastal", "1.0", "turbid"};

// Electrons -> 8-bit BGR with one fixed exposure and a display gamma.
cv::Mat Display(const cv::Mat& electrons, double full_scale) {
  cv::Mat bgr(electrons.size(), CV_8UC3);
  for (int y = 0; y < electrons.rows; ++y) {
    for (int x = 0; x < electrons.cols; ++x) {
      const cv::Vec3f e = electrons.at<cv::Vec3f>(y, x);
      for (int k = 0; k < 3; ++k) {
        const double v = std::pow(std::clamp(e[k] / full_scale, 0.0, 1.0), 1 / 2.2);
        bgr.at<cv::Vec3b>(y, x)[2 - k] = cv::saturate_cast<uchar>(255 * v);
      }
    }
  }
  return bgr;
}

// Mean green profile across the line, offsets -40..40 px, laser only.
std::vector<double> LineProfile(const std::string& water) {
  const Renderer renderer(testing::PlaneConfig(320, 240, water));
  FrameState state;
  state.world_from_camera = testing::LookingDown(2.0);
  state.laser_angles_rad = {-0.1};
  const cv::Mat electrons = renderer.Render(state).electrons;
  const auto truth = renderer.LaserGroundTruth(state, 0.5);
  std::vector<double> profile(81, 0.0);
  int rows = 0;
  for (int row = 60; row < 180; ++row) {
    const auto u = testing::TruthAtRow(truth, row);
    if (!u) continue;
    const int centre = static_cast<int>(std::round(*u));
    for (int d = -40; d <= 40; ++d) profile[d + 40] += electrons.at<cv::Vec3f>(row, centre + d)[1];
    ++rows;
  }
  for (double& value : profile) value /= std::max(rows, 1);
  return profile;
}

TEST(FiguresTest, TurbidityStripAndProfiles) {
  // Image strip: frame 30 of tank-target (laser on the board).
  std::vector<cv::Mat> tiles;
  std::vector<double> mean_green;
  for (const auto& water : kWaters) {
    ScenarioOptions options;
    options.width = 320;
    options.height = 240;
    options.turbidity = water;
    options.output = OutputFormat::kRgb;
    const Scenario scenario = MakeScenario("tank-target", options);
    const Renderer renderer(scenario.config);
    const RenderedFrame frame = renderer.Render(scenario.FrameAt(Trajectory(scenario.motion), 30));
    tiles.push_back(Display(frame.electrons, 2500.0 /* full scale at gain 4 */));
    cv::putText(tiles.back(), water == "1.0" ? "c_p 1.0/m" : water, {8, 20},
                cv::FONT_HERSHEY_SIMPLEX, 0.6, {255, 255, 255}, 1);
    mean_green.push_back(cv::mean(frame.electrons)[1]);
  }
  // Profiles.
  std::vector<std::vector<double>> profiles;
  for (const auto& water : kWaters) profiles.push_back(LineProfile(water));
  const double top = *std::max_element(profiles[0].begin(), profiles[0].end());
  for (size_t w = 0; w < kWaters.size(); ++w) {
    const auto& p = profiles[w];
    std::cout << kWaters[w] << ": peak " << *std::max_element(p.begin(), p.end())
              << " e-, at +-30 px " << 0.5 * (p[10] + p[70]) << " e-\n";
  }
  // The line dims with turbidity.
  EXPECT_GT(*std::max_element(profiles[0].begin(), profiles[0].end()),
            *std::max_element(profiles[1].begin(), profiles[1].end()));
  for (size_t k = 1; k + 1 < profiles.size(); ++k) {
    EXPECT_GT(*std::max_element(profiles[k].begin(), profiles[k].end()),
              *std::max_element(profiles[k + 1].begin(), profiles[k + 1].end()));
  }

  const char* dir = std::getenv("UWSCAN_FIGURE_DIR");
  if (!dir) return;
  cv::Mat strip;
  cv::hconcat(tiles, strip);
  ASSERT_TRUE(cv::imwrite(std::string(dir) + "/sim_turbidity_strip.png", strip));
  // Log-scale plot, 1e-6 .. 1 of the clear-water peak.
  const int w = 640, h = 360, margin = 40;
  cv::Mat plot(h, w, CV_8UC3, cv::Scalar(255, 255, 255));
  const cv::Scalar colours[4] = {{200, 120, 0}, {0, 160, 0}, {0, 120, 220}, {0, 0, 200}};
  auto to_point = [&](int i, double value) {
    const double y = std::log10(std::max(value / top, 1e-6)) / -6.0;  // 0 top, 1 bottom
    return cv::Point(margin + i * (w - 2 * margin) / 80,
                     margin + static_cast<int>(y * (h - 2 * margin)));
  };
  cv::rectangle(plot, {margin, margin}, {w - margin, h - margin}, {0, 0, 0});
  for (int decade = 0; decade <= 6; ++decade) {
    const int y = margin + decade * (h - 2 * margin) / 6;
    cv::line(plot, {margin, y}, {w - margin, y}, {220, 220, 220});
    cv::putText(plot, "1e-" + std::to_string(decade), {2, y + 4}, cv::FONT_HERSHEY_PLAIN, 0.8,
                {0, 0, 0});
  }
  for (size_t k = 0; k < profiles.size(); ++k) {
    for (int i = 1; i <= 80; ++i) {
      cv::line(plot, to_point(i - 1, profiles[k][i - 1]), to_point(i, profiles[k][i]), colours[k],
               2);
    }
    cv::putText(plot, kWaters[k] == "1.0" ? "c_p 1.0/m" : kWaters[k],
                {w - margin - 90, margin + 20 + 18 * static_cast<int>(k)}, cv::FONT_HERSHEY_SIMPLEX,
                0.5, colours[k], 1);
  }
  cv::putText(plot, "green signal across the laser line (-40..40 px), relative to clear peak",
              {margin, h - 12}, cv::FONT_HERSHEY_PLAIN, 1.0, {0, 0, 0});
  ASSERT_TRUE(cv::imwrite(std::string(dir) + "/sim_turbidity_profile.png", plot));
}

TEST(FiguresTest, ScenarioGallery) {
  std::vector<cv::Mat> tiles;
  for (const std::string& name : ScenarioNames()) {
    ScenarioOptions options;
    options.width = 320;
    options.height = 240;
    options.frames = 5;
    options.output = OutputFormat::kRgb;
    const Scenario scenario = MakeScenario(name, options);
    const Renderer renderer(scenario.config);
    const FrameState state = scenario.FrameAt(Trajectory(scenario.motion), 2);
    cv::Mat image = renderer.Render(state).image;
    ASSERT_EQ(image.type(), CV_8UC3);
    EXPECT_GT(cv::mean(image)[2], 2.0) << name;  // lit, not black
    cv::putText(image, name, {8, 20}, cv::FONT_HERSHEY_SIMPLEX, 0.6, {255, 255, 255}, 1);
    tiles.push_back(image);
  }
  const char* dir = std::getenv("UWSCAN_FIGURE_DIR");
  if (!dir) return;
  tiles.push_back(cv::Mat::zeros(tiles[0].size(), tiles[0].type()));
  cv::Mat top, bottom, gallery;
  cv::hconcat(std::vector<cv::Mat>(tiles.begin(), tiles.begin() + 3), top);
  cv::hconcat(std::vector<cv::Mat>(tiles.begin() + 3, tiles.end()), bottom);
  cv::vconcat(top, bottom, gallery);
  ASSERT_TRUE(cv::imwrite(std::string(dir) + "/sim_scenarios.png", gallery));
}

}  // namespace
}  // namespace uwscan::sim
