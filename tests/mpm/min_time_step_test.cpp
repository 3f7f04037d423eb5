// time.min_time_step: a run whose stable step collapses stops with a message naming the criterion,
// the point and what to change, and leaves a restart, instead of crawling on at a vanishing step;
// without a floor, a step that falls a hundredfold below the run's largest is reported and the run goes on,
// and a step of zero stops the run as a collapse does.
// The case: one live point (20-sphere bonded cell) in a domain stretched homogeneously at 200 /s.
// Seed Eq. 4 bounds its step by q_h d_min / |ḣ|: about 0.01 × 3.4e-4 m / (200 /s × 1.4 mm) ≈ 1e-5 s,
// below a floor of 1e-4 s, while the same run without the floor goes on.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

#include "common/temporary_directory.hpp"
#include "mpm_solver/app/run_command.hpp"
#include "mpm_solver/io/scene_input.hpp"

namespace grainbank::mpm {
namespace {

const char* const kCell = R"({"material": {"density": 920, "k_n": 2000, "k_t": 600, "restitution": 0.3,
  "friction": 0.2, "bond": {"tensile_strength": 8e-4, "shear_strength": 9.6e-4, "exponent": 2, "bonding_distance": 0.05}},
  "effects": {"cohesion": true},
  "preparation": {"spheres": 20, "diameter": {"min": 3.4e-4, "max": 4.0e-4}, "pressure": 1000, "seed": 9}})";

std::string stretched_scene(const std::string& floor) {
  return R"({"grid": {"origin": [0, 0], "cell_size": 0.1, "cells": [6, 6]},
  "time": {"end": 2e-4, "output_interval": 1e-4, "max_time_step": 1e-3)" + floor + R"(},
  "effects": {"cohesion": true},
  "integration": {"homogeneous_drive": {"L": [[200, 0], [0, 0]], "origin": [0.3, 0.3]}},
  "materials": [{"name": "snow", "law": "live", "cell": "cell.json"}],
  "regions": [{"material": "snow", "rectangle": {"min": [0.25, 0.25], "max": [0.35, 0.35]}, "points_per_cell": 1}]})";
}

nlohmann::json run(const TemporaryDirectory& dir, const std::string& name, const std::string& floor) {
  dir.write("cell.json", kCell);
  app::RunOptions o;
  o.scene = dir.write(name + ".json", stretched_scene(floor));
  o.out = dir.path() / name;
  o.progress = false;
  return app::run_scene(o);
}

TEST(MinTimeStep, ACollapsedStepStopsTheRunNamingEquation4ThePointAndTheRemedy) {
  const TemporaryDirectory dir("gb_min_time_step");
  try {
    run(dir, "floored", R"(, "min_time_step": 1e-4)");
    FAIL() << "ran on below the floor";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    std::printf("%s\n", what.c_str());
    for (const char* part : {"the time step fell to", "below time.min_time_step = 0.0001 s", "seed Eq. 4",
                             "material point 0 (law live)", "raise the material's q_h", "restart written to"})
      EXPECT_NE(what.find(part), std::string::npos) << part << " not in: " << what;
  }
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "floored" / "restart.h5"));
  // Without the floor the same run goes on at the small step.
  const nlohmann::json summary = run(dir, "free", "");
  EXPECT_FALSE(summary["interrupted"].get<bool>());
  EXPECT_LT(summary["time_step"]["min"].get<double>(), 1e-4);
}

// One elastic point at the centre of a homogeneous expansion at 200 /s in both directions: it stays
// put while its volume grows as e^{400 t}, so its density falls and its wave speed sqrt(M V / m), with
// it the CFL step, grows as e^{200 t}. By 12 ms the step has fallen elevenfold, by 25 ms some
// 150-fold from the run's largest, its first.
nlohmann::json run_expanding_elastic(const TemporaryDirectory& dir, const std::string& name, double end) {
  app::RunOptions o;
  o.scene = dir.write(name + ".json", R"({"grid": {"origin": [0, 0], "cell_size": 0.1, "cells": [10, 6]},
    "time": {"end": )" + std::to_string(end) + R"(, "output_interval": 0.05, "max_time_step": 1e-2},
    "integration": {"homogeneous_drive": {"L": [[200, 0], [0, 200]], "origin": [0.55, 0.25]}},
    "materials": [{"name": "jelly", "law": "elastic", "density": 1000, "young": 1e6, "poisson": 0.3}],
    "regions": [{"material": "jelly", "rectangle": {"min": [0.5, 0.2], "max": [0.6, 0.3]}, "points_per_cell": 1}]})");
  o.out = dir.path() / name;
  o.progress = false;
  return app::run_scene(o);
}

TEST(MinTimeStep, AStepFallenAHundredfoldIsReportedNamingItsCriterionAndTheRunGoesOn) {
  const TemporaryDirectory dir("gb_step_fall");
  const nlohmann::json fallen = run_expanding_elastic(dir, "fallen", 0.025);
  EXPECT_FALSE(fallen["interrupted"].get<bool>());
  const double fall = fallen["time_step"]["max"].get<double>() / fallen["time_step"]["min"].get<double>();
  EXPECT_GT(fall, 100);
  EXPECT_LT(fall, 1000);
  const nlohmann::json& reports = fallen["time_step"]["falls"];
  ASSERT_EQ(reports.size(), 1u) << reports.dump();
  const std::string report = reports[0].get<std::string>();
  for (const char* part : {"the time step fell to", "of the run's largest", "CFL criterion",
                           "time.min_time_step stops a run"})
    EXPECT_NE(report.find(part), std::string::npos) << part << " not in: " << report;
  // An elevenfold fall is no collapse.
  const nlohmann::json slowed = run_expanding_elastic(dir, "slowed", 0.012);
  EXPECT_GT(slowed["time_step"]["max"].get<double>() / slowed["time_step"]["min"].get<double>(), 5);
  EXPECT_TRUE(slowed["time_step"]["falls"].empty()) << slowed["time_step"]["falls"].dump();
}

// A material so light (1e-320 kg/m³, a subnormal number) that its wave speed sqrt(M / ρ) overflows:
// the CFL step is 0 from the first step, which no run can take, with or without a floor.
TEST(MinTimeStep, AStepOfZeroStopsTheRunNamingItsCriterion) {
  const TemporaryDirectory dir("gb_zero_step");
  app::RunOptions o;
  o.scene = dir.write("weightless.json", R"({"grid": {"origin": [0, 0], "cell_size": 0.1, "cells": [6, 6]},
    "time": {"end": 0.01, "output_interval": 0.005, "max_time_step": 1e-3},
    "materials": [{"name": "ghost", "law": "elastic", "density": 1e-320, "young": 1e6, "poisson": 0.3}],
    "regions": [{"material": "ghost", "rectangle": {"min": [0.2, 0.2], "max": [0.4, 0.4]}, "points_per_cell": 1}]})");
  o.out = dir.path() / "weightless";
  o.progress = false;
  try {
    app::run_scene(o);
    FAIL() << "ran at a step of zero";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    std::printf("%s\n", what.c_str());
    for (const char* part : {"the time step fell to 0 s at t = 0 s", "which no step can advance", "CFL criterion",
                             "restart written to"})
      EXPECT_NE(what.find(part), std::string::npos) << part << " not in: " << what;
  }
}

TEST(MinTimeStep, AFloorAboveTheCapIsRefused) {
  const TemporaryDirectory dir("gb_min_time_step_keys");
  dir.write("cell.json", kCell);
  try {
    io::load_scene(dir.write("bad.json", stretched_scene(R"(, "min_time_step": 1e-2)")));
    FAIL() << "accepted a floor above max_time_step";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("min_time_step"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace grainbank::mpm
