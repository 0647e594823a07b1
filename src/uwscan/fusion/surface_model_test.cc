#include "uwscan/fusion/surface_model.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "uwscan/sim/scenario.h"
#include "uwscan/sim/testing.h"

namespace uwscan::fusion {
namespace {

// A simulator scenario at 320x240 and surface models swept by its true
// laser profiles (the simulator's laser points, true poses), with the first
// frame as their reference view.
struct SimulatedSweep {
  SimulatedSweep(const std::string& name, int frames)
      : scenario(sim::testing::SmallScenario(name, frames)),
        renderer(scenario.config),
        trajectory(scenario.motion),
        world_from_first(trajectory.WorldFromCamera(0.0)) {}
  const Camera& camera() const { return renderer.camera(); }
  // Every `step`th frame's profile.
  SurfaceModel Sweep(const SurfaceModelOptions& options, int step = 1) const {
    SurfaceModel surface(camera(), world_from_first, options);
    for (int frame = 0; frame < scenario.frames; frame += step) {
      const sim::FrameState state = scenario.FrameAt(trajectory, frame);
      laser::Profile profile;
      for (const auto& p : renderer.LaserGroundTruth(state)) {
        profile.points.push_back({p.point_in_camera, p.pixel, 1.0f});
      }
      surface.AddProfile(state.world_from_camera, profile);
    }
    return surface;
  }
  sim::Scenario scenario;
  sim::Renderer renderer;
  sim::Trajectory trajectory;
  Rigid3d world_from_first;
};

// A laser line across x on a floor 2 m ahead (z = 2, camera frame) at y,
// points 1 cm apart.
laser::Profile FloorLine(double y) {
  laser::Profile profile;
  for (double x = -0.6; x <= 0.6; x += 0.01)
    profile.points.push_back({Eigen::Vector3d(x, y, 2.0), Eigen::Vector2d::Zero(), 1.0f});
  return profile;
}

// Profiles of a laser sweeping a tank floor (from the simulator's true laser
// points) give rays through the swept region their true depth.
TEST(SurfaceModel, RaysMeetTheSweptSurface) {
  const SimulatedSweep tank("tank-target", 12);
  const Camera& camera = tank.camera();
  const Rigid3d& world_from_first = tank.world_from_first;
  SurfaceModelOptions options_local;
  options_local.extrapolate_plane = false;
  const SurfaceModel surface = tank.Sweep(options_local);
  ASSERT_GT(surface.size(), 500);
  int hits = 0, misses = 0;
  double worst = 0.0;
  for (int v = 10; v < camera.height; v += 20) {
    for (int u = 10; u < camera.width; u += 20) {
      const auto ray = camera.BackProject(Eigen::Vector2d(u, v));
      ASSERT_TRUE(ray.has_value());
      const Eigen::Vector3d origin = world_from_first * ray->origin;
      const Eigen::Vector3d direction = world_from_first.rotation * ray->direction;
      const auto truth = tank.scenario.config.scene.Intersect(origin, direction);
      const auto hit = surface.Intersect(origin, direction);
      if (!hit) {
        ++misses;
        continue;
      }
      ++hits;
      ASSERT_TRUE(truth.has_value());
      worst = std::max(worst, (hit->point - truth->point_world).norm());
    }
  }
  EXPECT_GT(hits, 20);
  EXPECT_LT(worst, 0.008) << hits << " hits";  // the 5 mm board edge is smoothed over
  EXPECT_GT(misses, 0);                        // not swept yet: no depth rather than a guess
}

// A single profile over a hull with a shaft in front of it spreads across
// its longest direction, but within the laser sheet: its best plane is the
// sheet, not the surface. No dominant plane until profiles lie apart across
// the line; then the surface's.
// Points are binned into the reference view's cells only when the cells
// are read: a surface queried after every profile (binning each time) and
// one queried once at the end hold the same points and give the same hits,
// and a query sees the profile added just before it.
TEST(SurfaceModel, BinningWhenReadEqualsBinningAsAdded) {
  const SimulatedSweep tank("tank-target", 12);
  const Camera& camera = tank.camera();
  SurfaceModelOptions options;
  options.extrapolate_plane = false;
  options.max_points_per_cell = 6;  // full cells: the round-robin order matters
  const SurfaceModel at_once = tank.Sweep(options);
  SurfaceModel as_added(camera, tank.world_from_first, options);
  long size_before = 0;
  for (int frame = 0; frame < tank.scenario.frames; ++frame) {
    const sim::FrameState state = tank.scenario.FrameAt(tank.trajectory, frame);
    laser::Profile profile;
    for (const auto& p : tank.renderer.LaserGroundTruth(state))
      profile.points.push_back({p.point_in_camera, p.pixel, 1.0f});
    as_added.AddProfile(state.world_from_camera, profile);
    const long size = as_added.size();
    EXPECT_GT(size, size_before) << "frame " << frame;
    size_before = size;
  }
  ASSERT_EQ(as_added.size(), at_once.size());
  int hits = 0;
  for (int v = 10; v < camera.height; v += 10) {
    for (int u = 10; u < camera.width; u += 10) {
      const auto ray = camera.BackProject(Eigen::Vector2d(u, v));
      ASSERT_TRUE(ray.has_value());
      const Eigen::Vector3d origin = tank.world_from_first * ray->origin;
      const Eigen::Vector3d direction = tank.world_from_first.rotation * ray->direction;
      const auto a = as_added.Intersect(origin, direction),
                 b = at_once.Intersect(origin, direction);
      ASSERT_EQ(a.has_value(), b.has_value()) << u << ", " << v;
      if (!a) continue;
      ++hits;
      EXPECT_EQ(a->point, b->point) << u << ", " << v;
    }
  }
  // (Six points a cell: only rays within max_local_gap_m of one hit.)
  EXPECT_GT(hits, 30);
}

// Points a hair's breadth (1e-5 px) either side of a cell's edge and of
// the image's edges go where their exact pixel says. Groups of four fill a
// cell of four: two groups that shared a cell would count four points, not
// eight, and a group counted outside the image or inside it wrongly would
// change the count too.
TEST(SurfaceModel, PointsBesideACellsEdgeAreBinnedByTheExactPixel) {
  Camera camera = Camera::Flat1();
  camera.distortion = {-0.25, 0.08, 0.001, -0.0015, -0.01};
  SurfaceModelOptions options;
  options.max_points_per_cell = 4;
  SurfaceModel surface(camera, Rigid3d(), options);
  const double hair = 1e-5, cell = options.cell_px;
  laser::Profile profile;
  int inside_groups = 0;
  auto add_group = [&](double x, double y) {
    for (double depth : {0.5, 1.0, 2.0, 3.0}) {
      const auto ray = camera.BackProject(Eigen::Vector2d(x, y));
      ASSERT_TRUE(ray.has_value());
      const Eigen::Vector3d point = ray->At((depth - ray->origin.z()) / ray->direction.z());
      profile.points.push_back({point, Eigen::Vector2d(x, y), 1.0f});
    }
    inside_groups += camera.InImage(Eigen::Vector2d(x, y));
  };
  // Column edges on rows of their own, row edges on columns of their own.
  for (int k = 1; k < 8; ++k) {
    const double row_y = (3 * k + 0.5) * cell, edge_x = 9 * k * cell - 0.5;
    add_group(edge_x - hair, row_y);
    add_group(edge_x + hair, row_y);
    const double column_x = (9 * k + 4.5) * cell, edge_y = 7 * k * cell - 0.5;
    add_group(column_x, edge_y - hair);
    add_group(column_x, edge_y + hair);
  }
  // The image's edges.
  for (const double side : {-1.0, 1.0}) {
    add_group(-0.5 + side * hair, 100.0);
    add_group(camera.width - 0.5 + side * hair, 300.0);
    add_group(700.0, -0.5 + side * hair);
    add_group(900.0, camera.height - 0.5 + side * hair);
  }
  surface.AddProfile(Rigid3d(), profile);
  EXPECT_EQ(inside_groups, 32);
  EXPECT_EQ(surface.size(), 4 * inside_groups);
}

TEST(SurfaceModel, OneProfileGivesNoPlane) {
  const Camera camera = Camera::Flat1();
  // A hull of 4 m radius, z = 2 + x^2 / 8 (camera frame), and a shaft at
  // z = 1.3 for |x| < 0.12; sheets y = const.
  const auto profile_at = [](double y, bool shaft) {
    laser::Profile profile;
    for (double x = -0.6; x <= 0.6; x += 0.01) {
      const double z = shaft && std::abs(x) < 0.12 ? 1.3 : 2.0 + x * x / 8.0;
      profile.points.push_back({Eigen::Vector3d(x, y, z), Eigen::Vector2d::Zero(), 1.0f});
    }
    return profile;
  };
  SurfaceModel with_shaft(camera, Rigid3d(), SurfaceModelOptions{});
  with_shaft.AddProfile(Rigid3d(), profile_at(0.0, true));
  EXPECT_FALSE(with_shaft.HasDominantPlane());

  SurfaceModel hull(camera, Rigid3d(), SurfaceModelOptions{});
  for (double y = 0.0; y <= 0.1; y += 0.01) hull.AddProfile(Rigid3d(), profile_at(y, false));
  ASSERT_TRUE(hull.HasDominantPlane());
  // Beyond the swept band: the extrapolated plane is the surface's (z ~ 2),
  // not the sheet's (y ~ 0.05).
  const auto hit =
      hull.Intersect(Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0.15, 1).normalized());
  ASSERT_TRUE(hit.has_value());
  EXPECT_TRUE(hit->extrapolated);
  EXPECT_NEAR(hit->point.z(), 2.015, 0.03) << hit->point.transpose();
  EXPECT_NEAR(hit->point.y(), 0.3, 0.01);
}

// The dominant plane from a band of lines narrower than
// settled_plane_width_m gives provisional hits; once the lines spread wider
// across, the same ray's hit is settled. Lines 1 cm apart on a floor
// 2 m ahead (z = 2), across y.
TEST(SurfaceModel, APlaneOnANarrowBandIsProvisional) {
  const Camera camera = Camera::Flat1();
  SurfaceModelOptions options;
  SurfaceModel floor(camera, Rigid3d(), options);
  const Eigen::Vector3d far_ray = Eigen::Vector3d(0, -0.3, 1).normalized();  // 60 cm off
  double y = 0.0;
  for (; y <= 0.08; y += 0.01) floor.AddProfile(Rigid3d(), FloorLine(y));
  ASSERT_TRUE(floor.HasDominantPlane());  // 9 cm: over min_plane_width_m, under 15 cm
  auto hit = floor.Intersect(Eigen::Vector3d::Zero(), far_ray);
  ASSERT_TRUE(hit.has_value());
  EXPECT_TRUE(hit->extrapolated);
  EXPECT_TRUE(hit->provisional);
  EXPECT_NEAR(hit->point.z(), 2.0, 1e-6);
  // A ray through the band is measured there, never provisional.
  const auto measured =
      floor.Intersect(Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0.02, 1).normalized());
  ASSERT_TRUE(measured.has_value());
  EXPECT_FALSE(measured->extrapolated);
  EXPECT_FALSE(measured->provisional);

  for (; y <= 0.2; y += 0.01) floor.AddProfile(Rigid3d(), FloorLine(y));  // 21 cm now
  hit = floor.Intersect(Eigen::Vector3d::Zero(), far_ray);
  ASSERT_TRUE(hit.has_value());
  EXPECT_TRUE(hit->extrapolated);
  EXPECT_FALSE(hit->provisional);

  // With settled_plane_width_m = 0 no hit is ever provisional.
  options.settled_plane_width_m = 0.0;
  SurfaceModel unchecked(camera, Rigid3d(), options);
  for (double yy = 0.0; yy <= 0.08; yy += 0.01) unchecked.AddProfile(Rigid3d(), FloorLine(yy));
  hit = unchecked.Intersect(Eigen::Vector3d::Zero(), far_ray);
  ASSERT_TRUE(hit.has_value());
  EXPECT_FALSE(hit->provisional);
}

// How squarely the reference view sees the dominant plane: the camera's
// distance to it over the median distance to its points, checked against
// the same computed from the profiles' points. Face on (z = 2), turned by
// 60 deg about the line (distance 1 m), and a plane that runs 6 cm beside
// the camera: copies of one profile (the line at y = 0.1, z = 2) spread in
// range along the lines from that point, as profiles of a slow sweep are
// when placed with too little motion (tank seed 103 at 14.4 Hz,
// BENCHMARKS.md).
TEST(SurfaceModel, ViewCosineSaysHowSquarelyThePlaneIsSeen) {
  const Camera camera = Camera::Flat1();
  const auto expected = [](const std::vector<laser::Profile>& profiles, double distance_m) {
    std::vector<double> ranges;
    for (const auto& profile : profiles)
      for (const auto& p : profile.points) ranges.push_back(p.point_in_camera.norm());
    std::sort(ranges.begin(), ranges.end());
    return distance_m / ranges[ranges.size() / 2];
  };
  const auto cosine = [&camera](const std::vector<laser::Profile>& profiles) {
    SurfaceModel surface(camera, Rigid3d(), SurfaceModelOptions{});
    for (const auto& profile : profiles) surface.AddProfile(Rigid3d(), profile);
    EXPECT_TRUE(surface.HasDominantPlane());
    return surface.DominantPlaneViewCosine().value_or(-1.0);
  };

  std::vector<laser::Profile> face_on, turned, through;
  const Eigen::AngleAxisd turn(60.0 * M_PI / 180.0, Eigen::Vector3d::UnitX());
  const Eigen::Vector3d pivot(0.0, 0.0, 2.0), beside(0.0, 0.06, 0.0);
  for (int i = 0; i <= 10; ++i) {
    face_on.push_back(FloorLine(0.01 * i));
    turned.push_back(FloorLine(0.01 * i));
    for (auto& p : turned.back().points)
      p.point_in_camera = pivot + turn * (p.point_in_camera - pivot);
    through.push_back(FloorLine(0.1));
    for (auto& p : through.back().points)
      p.point_in_camera = beside + (0.85 + 0.03 * i) * (p.point_in_camera - beside);
  }
  EXPECT_NEAR(cosine(face_on), expected(face_on, 2.0), 1e-9);
  EXPECT_NEAR(cosine(turned), expected(turned, 1.0), 1e-9);
  // The plane through `beside` and the line: normal along x x (0, 0.04, 2).
  const Eigen::Vector3d normal =
      Eigen::Vector3d::UnitX().cross(Eigen::Vector3d(0, 0.04, 2)).normalized();
  const double through_cosine = cosine(through);
  EXPECT_NEAR(through_cosine, expected(through, std::abs(normal.dot(beside))), 1e-9);
  EXPECT_LT(through_cosine, 0.05);
  // Without a plane, none.
  EXPECT_FALSE(SurfaceModel(camera, Rigid3d(), SurfaceModelOptions{}).DominantPlaneViewCosine());
}

// A local plane is a measurement only where its points are: a hit of the
// plane fitted around the band's edge that lies centimetres past the last
// profile is as much an extrapolation as the dominant plane's farther out
// (and past a shaft's silhouette, where its tangent plane runs on in front
// of the hull, it is wrong: coastal hull seed 79, BENCHMARKS.md).
TEST(SurfaceModel, LocalPlaneIsMeasuredOnlyNearItsPoints) {
  const auto floor_z = [](double y) { return 2.0 + 0.2 * y; };  // tilted
  // Sheets y = 0 ... 0.1 m, 5 mm apart, points 1 cm apart along them.
  const auto swept = [&](const SurfaceModelOptions& options) {
    SurfaceModel surface(Camera::Flat1(), Rigid3d(), options);
    for (double y = 0.0; y <= 0.1001; y += 0.005) {
      laser::Profile profile;
      for (double x = -0.6; x <= 0.6; x += 0.01)
        profile.points.push_back(
            {Eigen::Vector3d(x, y, floor_z(y)), Eigen::Vector2d::Zero(), 1.0f});
      surface.AddProfile(Rigid3d(), profile);
    }
    return surface;
  };
  const auto ray_to = [&](double y) { return Eigen::Vector3d(0.003, y, floor_z(y)).normalized(); };
  const SurfaceModelOptions options;
  const SurfaceModel surface = swept(options);
  ASSERT_TRUE(surface.HasDominantPlane());
  const auto hit_at = [&](double y) {
    return surface.Intersect(Eigen::Vector3d::Zero(), ray_to(y));
  };
  for (const double y : {0.05, 0.11}) {  // in the band, and 1 cm past its last profile
    const auto hit = hit_at(y);
    ASSERT_TRUE(hit.has_value()) << y;
    EXPECT_FALSE(hit->extrapolated) << y;
    EXPECT_EQ(hit->sigma_m, options.local_sigma_m) << y;
    EXPECT_NEAR(hit->point.z(), floor_z(y), 0.001) << y;
  }
  // 4 cm past it: still within the cells the band's edge is fitted on,
  // but farther than max_local_gap_m from every point.
  const auto beyond = hit_at(0.14);
  ASSERT_TRUE(beyond.has_value());
  EXPECT_TRUE(beyond->extrapolated);
  EXPECT_EQ(beyond->sigma_m, options.extrapolated_sigma_m);
  EXPECT_NEAR(beyond->point.z(), floor_z(0.14), 0.002);
  // (Without the gap test the local plane's hit there counts as measured.)
  SurfaceModelOptions no_gap;
  no_gap.max_local_gap_m = 1.0;
  const auto ungapped = swept(no_gap).Intersect(Eigen::Vector3d::Zero(), ray_to(0.14));
  ASSERT_TRUE(ungapped.has_value());
  EXPECT_FALSE(ungapped->extrapolated);
  EXPECT_EQ(ungapped->point, beyond->point);
  // Without the dominant plane to extrapolate with, no depth there.
  SurfaceModelOptions local_only;
  local_only.extrapolate_plane = false;
  const SurfaceModel measured = swept(local_only);
  EXPECT_TRUE(measured.Intersect(Eigen::Vector3d::Zero(), ray_to(0.05)));
  EXPECT_FALSE(measured.Intersect(Eigen::Vector3d::Zero(), ray_to(0.14)));
}

// A shaft 0.6 m in front of a flat hull, on a quarter of every profile,
// must not tilt the dominant plane the rest of the view takes its depth
// from (RANSAC before the reweighted fit).
TEST(SurfaceModel, DominantPlaneIgnoresAShaftInFront) {
  const Camera camera = Camera::Flat1();
  SurfaceModel surface(camera, Rigid3d(), SurfaceModelOptions{});
  for (double y = -0.05; y <= 0.05; y += 0.005) {
    laser::Profile profile;
    for (double x = -0.6; x <= 0.6; x += 0.01) {
      const double z = x > 0.3 ? 1.4 : 2.0;  // the shaft on the right quarter
      profile.points.push_back({Eigen::Vector3d(x, y, z), Eigen::Vector2d::Zero(), 1.0f});
    }
    surface.AddProfile(Rigid3d(), profile);
  }
  ASSERT_TRUE(surface.HasDominantPlane());
  for (const double x : {-0.4, 0.0}) {
    const auto hit =
        surface.Intersect(Eigen::Vector3d::Zero(), Eigen::Vector3d(x, 0.3, 2.0).normalized());
    ASSERT_TRUE(hit.has_value());
    EXPECT_TRUE(hit->extrapolated);
    EXPECT_NEAR(hit->point.z(), 2.0, 0.01) << hit->point.transpose();
  }
}

// The simulator's hull: the servo sweeps the line over the hull and the
// shaft in front of it while the platform moves along. Swept with the true
// poses over the whole scan (what a first pass measures), rays from the
// first view to the shaft must take the shaft's depth, not the hull's 0.7 m
// behind it: where the line never reached the shaft from there (continued
// from its measured cross-section), and where hull points measured from
// elsewhere lie behind it in the same cells of the first view.
TEST(SurfaceModel, ShaftInFrontOfTheHullKeepsItsOwnDepth) {
  const SimulatedSweep hull("hull", 200);
  const Camera& camera = hull.camera();
  const Rigid3d& world_from_first = hull.world_from_first;
  const sim::Scene& scene = hull.scenario.config.scene;
  int shaft = -1;
  for (size_t i = 0; i < scene.surfaces.size(); ++i) {
    if (scene.surfaces[i].name == "shaft") shaft = static_cast<int>(i);
  }
  ASSERT_GE(shaft, 0);
  // Median absolute range error on the shaft's and on the hull's rays.
  const auto errors = [&](const SurfaceModel& surface) {
    std::vector<double> on_shaft, on_hull;
    for (int v = 4; v < camera.height; v += 8) {
      for (int u = 4; u < camera.width; u += 8) {
        const auto ray = camera.BackProject(Eigen::Vector2d(u, v));
        if (!ray) continue;
        const Eigen::Vector3d origin = world_from_first * ray->origin;
        const Eigen::Vector3d direction = world_from_first.rotation * ray->direction;
        const auto truth = scene.Intersect(origin, direction);
        const auto hit = surface.Intersect(origin, direction);
        if (!truth || !hit) continue;
        const double error = std::abs((hit->point - origin).norm() - truth->lambda);
        (truth->surface == shaft ? on_shaft : on_hull).push_back(error);
      }
    }
    std::sort(on_shaft.begin(), on_shaft.end());
    std::sort(on_hull.begin(), on_hull.end());
    return std::pair{on_shaft, on_hull};
  };
  const auto quantile = [](const std::vector<double>& v, double q) {
    return v.empty() ? 1e9 : v[static_cast<size_t>(q * (v.size() - 1))];
  };
  const SurfaceModel surface = hull.Sweep({}, 2);
  ASSERT_TRUE(surface.HasFrontSurface());
  const auto [on_shaft, on_hull] = errors(surface);
  ASSERT_GT(on_shaft.size(), 150u);
  ASSERT_GT(on_hull.size(), 500u);
  EXPECT_LT(quantile(on_shaft, 0.5), 0.02);
  EXPECT_LT(quantile(on_shaft, 0.8), 0.05);
  EXPECT_LT(quantile(on_hull, 0.5), 0.02);
  EXPECT_LT(quantile(on_hull, 0.9), 0.05);
  std::printf(
      "range error, median / 80 %% / 90 %%: shaft %.3f / %.3f / %.3f m (%zu rays), hull "
      "%.3f / %.3f / %.3f m (%zu)\n",
      quantile(on_shaft, 0.5), quantile(on_shaft, 0.8), quantile(on_shaft, 0.9), on_shaft.size(),
      quantile(on_hull, 0.5), quantile(on_hull, 0.8), quantile(on_hull, 0.9), on_hull.size());
  // Without a surface in front (a threshold no sample reaches), the shaft
  // takes the hull's depth.
  SurfaceModelOptions no_front;
  no_front.front_min_fraction = 1.0;
  const SurfaceModel without = hull.Sweep(no_front, 2);
  EXPECT_FALSE(without.HasFrontSurface());
  EXPECT_GT(quantile(errors(without).first, 0.5), 0.3);
}

}  // namespace
}  // namespace uwscan::fusion
