// A single live-DEM point under a homogeneous deformation reproduces `dem_sampler run` (the same
// path driver, app::drive_along_path) along the same history of increments, to round-off.
//
// With MUSL a lone free point always sees L = 0 (every node it touches gets its own velocity), so
// the solver drives the domain kinematically (SolverSettings::homogeneous_drive): every node gets
// v_i = L (x_i - x_0). Cubic B-splines reproduce linear fields, so the point's velocity gradient is L
// and it moves affinely. dem_sampler and the MPM both build F_inc = exp(L Δt), so both cells receive
// the same increments.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <utility>

#include "dem_sampler/cell/matrix_functions.hpp"
#include "dem_sampler/cell/preparation.hpp"
#include "dem_sampler/cell/snow_preset.hpp"
#include "mpm_solver/dem_laws/live_dem_law.hpp"
#include "common/temporary_directory.hpp"
#include "mpm_solver/core/solver.hpp"
#include "mpm_solver/io/scene_input.hpp"
#include "dem_sampler/driver/path_driver.hpp"

namespace grainbank::mpm {
namespace {

TEST(HomogeneousLive, SinglePointReproducesDemSamplerRunAlongTheSamePath) {
  const dem::DemCell cell_template = dem::prepare_cell(dem::snow_material(), dem::snow_preparation(30, 5));
  app::PathSpec path;
  path.record_interval = 2e-4;
  path.substepping = {0.1, 1, 0.2};
  dem::Mat3 shear = dem::Mat3::Zero(), compression = dem::Mat3::Zero();
  shear(0, 1) = 2;
  compression(0, 0) = 0.5, compression(1, 1) = -1;
  path.segments = {{shear, 10 * path.record_interval}, {compression, 5 * path.record_interval}};

  // dem_sampler run: the stand-alone cell driven along the path.
  dem::DemCell alone = cell_template;
  std::vector<app::PathRecord> records;
  app::drive_along_path(alone, path, [&](const app::PathRecord& r) { records.push_back(r); });

  // The MPM: one live point in a homogeneously driven domain, stepped by Solver::step.
  LiveDemSettings settings;
  settings.substepping = path.substepping;
  Solver solver(Grid(Vec2(0, 0), 0.1, 8, 8), SolverSettings{});
  const std::size_t law = solver.add_law(std::make_unique<LiveDemLaw>(cell_template, settings));
  const Vec2 x0(0.43, 0.37);
  solver.add_point(law, x0, 1e-2, 0.05);

  double worst_stress = 0, worst_volume = 0, worst_gradient = 0;
  std::size_t record = 1;
  Vec2 affine_position = x0;
  for (const app::PathSegment& segment : path.segments) {
    const double dt = path.record_interval;
    const Mat2 L = segment.L.topLeftCorner<2, 2>();
    solver.set_homogeneous_drive(HomogeneousDrive{L, x0, std::nullopt});
    for (int k = 0; k < std::lround(segment.duration / dt); ++k, ++record) {
      solver.step(dt);
      const MaterialPoint& mp = solver.points()[0];  // re-read: the solver re-sorts its points
      affine_position = x0 + (Mat2::Identity() + dt * L) * (affine_position - x0);

      const app::PathRecord& r = records.at(record);
      const dem::Mat3& s = r.stress;
      const double scale = std::abs(s.trace());
      worst_gradient = std::max(worst_gradient, (mp.velocity_gradient - L).norm() / L.norm());
      worst_stress = std::max({worst_stress, std::abs(mp.stress.in_plane(0, 0) - s(0, 0)) / scale,
                               std::abs(mp.stress.in_plane(1, 1) - s(1, 1)) / scale,
                               std::abs(mp.stress.in_plane(0, 1) - 0.5 * (s(0, 1) + s(1, 0))) / scale,
                               std::abs(mp.stress.zz - s(2, 2)) / scale});
      worst_volume = std::max(worst_volume, std::abs(mp.volume / mp.initial_volume - r.F.determinant()));
      EXPECT_NEAR(solver.law(law).damage(mp.slot), r.measures.damage, 1e-15);
    }
  }
  std::printf("largest relative deviations from dem_sampler run: L %.2g, stress %.2g, volume ratio %.2g\n",
              worst_gradient, worst_stress, worst_volume);
  EXPECT_LT(worst_gradient, 1e-12);  // B-spline linear completeness, to round-off
  EXPECT_LT(worst_stress, 1e-10);
  EXPECT_LT(worst_volume, 1e-12);
  EXPECT_LT((solver.points()[0].position - affine_position).norm(), 1e-14);  // the point moved with the imposed field
  EXPECT_EQ(record, records.size());
  // The path did something: sheared and compressed the cell.
  EXPECT_GT(std::abs(records.back().stress(0, 1)) + std::abs(records.back().stress(1, 1) - records.front().stress(1, 1)),
            1.0);
}

}  // namespace
}  // namespace grainbank::mpm

namespace grainbank::mpm {
namespace {

// An elastic block under the scene key integration.homogeneous_drive = `drive`.
std::string scene(const std::string& drive) {
  return R"({"grid": {"origin": [0, 0], "cell_size": 0.1, "cells": [10, 10]},
    "time": {"end": 0.01, "output_interval": 0.01},
    "integration": {"transfer": "pic", "homogeneous_drive": )" + drive + R"(},
    "materials": [{"name": "a", "law": "elastic", "density": 1000, "young": 1e6, "poisson": 0.3}],
    "regions": [{"material": "a", "rectangle": {"min": [0.3, 0.3], "max": [0.6, 0.5]}, "points_per_cell": 2}]})";
}

TEST(HomogeneousLive, SceneDrivesEveryPointWithItsVelocityGradient) {
  // The scene key integration.homogeneous_drive reaches the solver: every point of a block follows
  // F = exp(Δt L)^n exactly, and a malformed L is refused naming its JSON path.
  const TemporaryDirectory folder("homogeneous-scene");
  io::Scene s = io::load_scene(folder.write("scene.json", scene(R"({"L": [[0.5, 2], [0, -0.5]], "origin": [0.45, 0.4]})")));
  Mat2 L;
  L << 0.5, 2, 0, -0.5;
  const double dt = 1e-3;
  dem::Mat3 L3 = dem::Mat3::Zero();
  L3.topLeftCorner<2, 2>() = L * dt;
  const Mat2 increment = dem::matrix_exponential(L3).topLeftCorner<2, 2>();
  Mat2 expected = Mat2::Identity();
  for (int k = 0; k < 10; ++k, expected = increment * expected) s.solver->step(dt);
  ASSERT_GT(s.solver->points().size(), 10u);
  for (const MaterialPoint& mp : s.solver->points())
    EXPECT_LT((mp.deformation_gradient - expected).norm(), 1e-12) << "point " << mp.id;

  const auto bad = folder.write("bad.json", scene(R"({"L": [[0.5, 2]]})"));
  try {
    io::load_scene(bad);
    FAIL() << "a one-row L must be refused";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("bad.json: /integration/homogeneous_drive/L"), std::string::npos) << e.what();
  }
}

TEST(HomogeneousLive, TheNormalStressKeyIsReadAndBadValuesAreRefusedByName) {
  const TemporaryDirectory folder("normal-stress-scene");
  const io::Scene s = io::load_scene(folder.write(
      "scene.json", scene(R"({"L": [[0, 2], [0, 0]], "normal_stress": {"stress": 500, "response_rate": 3}})")));
  const auto& control = s.solver->settings().homogeneous_drive->normal_stress;
  ASSERT_TRUE(control.has_value());
  EXPECT_EQ(control->stress, 500);
  EXPECT_EQ(control->response_rate, 3);
  EXPECT_EQ(control->integral_time, NormalStressControl{}.integral_time);

  const std::pair<const char*, const char*> refused[] = {
      {R"({"L": [[0, 2], [0, 0]], "normal_stress": {"stress": -500}})", "/integration/homogeneous_drive/normal_stress/stress"},
      {R"({"L": [[0, 2], [0, 0]], "normal_stress": {"stress": 500, "rate": 1}})", "/integration/homogeneous_drive/normal_stress"},
      {R"({"L": [[0, 0], [0, -1]], "normal_stress": {"stress": 500}})", "/integration/homogeneous_drive/L"}};
  for (const auto& [drive, where] : refused) {
    try {
      io::load_scene(folder.write("bad.json", scene(drive)));
      ADD_FAILURE() << "refused: " << drive;
    } catch (const std::exception& e) {
      EXPECT_NE(std::string(e.what()).find(std::string("bad.json: ") + where), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace grainbank::mpm
