// Only the effects a scene calls for: a library (or cell) built for another material or with other
// effects than the scene declares is refused with a message naming the difference; switched-off
// components are not built; negligible increments skip the constitutive call.
#include <gtest/gtest.h>

#include <fstream>

#include "common/json_input.hpp"
#include "tests/mpm/coupling_test_util.hpp"
#include "mpm_solver/io/scene_input.hpp"
#include "tests/mpm/mpm_test_util.hpp"

namespace grainbank::mpm {
namespace {

using namespace testing;

void write(const std::filesystem::path& file, const std::string& text) { std::ofstream(file) << text; }

// A scene with one hybrid material on the library `lib` (relative to the scene's folder).
std::string scene_json(const std::string& effects, const std::string& material_extra) {
  return R"({
  "grid": {"cell_size": 0.1, "cells": [6, 6]},
  "time": {"end": 0.001, "output_interval": 0.001},
  "effects": )" + effects + R"(,
  "materials": [{"name": "snow", "law": "hybrid", "library": "lib", "template": 1, "enrich": false)" +
         material_extra + R"(}],
  "regions": [{"material": "snow", "rectangle": {"min": [0.2, 0.2], "max": [0.4, 0.4]}}]
})";
}

// The error text of loading `scene`, or "" when it loads.
std::string load_error(const std::filesystem::path& scene) {
  try {
    io::load_scene(scene);
  } catch (const common::InputError& e) {
    return e.what();
  }
  return "";
}

class SceneOnLibrary : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = fresh_library_dir();
    std::filesystem::create_directories(folder_);
    ASSERT_EQ(create_library(folder_ / "lib", small_snow_cell()), 1);
  }
  std::filesystem::path folder_;
};

TEST_F(SceneOnLibrary, MatchingEffectsAndMaterialLoad) {
  write(folder_ / "cell.json", R"({"material": {"density": 920, "k_n": 2000, "k_t": 600, "restitution": 0.3,
    "friction": 0.2, "bond": {"tensile_strength": 8e-4, "shear_strength": 9.6e-4, "exponent": 2, "bonding_distance": 0.05}},
    "effects": {"cohesion": true},
    "preparation": {"spheres": 20, "diameter": {"min": 3.4e-4, "max": 4.0e-4}, "pressure": 1000, "seed": 9}})");
  write(folder_ / "scene.json", scene_json(R"({"cohesion": true, "kinetic_stress": false})", R"(, "cell": "cell.json")"));
  EXPECT_EQ(load_error(folder_ / "scene.json"), "");
}

TEST_F(SceneOnLibrary, ALibraryOfAnotherMaterialIsRefused) {
  write(folder_ / "cell.json", R"({"material": {"density": 920, "k_n": 2000, "k_t": 600, "restitution": 0.3,
    "friction": 0.3, "bond": {"tensile_strength": 8e-4, "shear_strength": 9.6e-4, "exponent": 2, "bonding_distance": 0.05}},
    "effects": {"cohesion": true},
    "preparation": {"spheres": 20, "diameter": {"min": 3.4e-4, "max": 4.0e-4}, "pressure": 1000, "seed": 9}})");
  write(folder_ / "scene.json", scene_json("{}", R"(, "cell": "cell.json")"));
  const std::string error = load_error(folder_ / "scene.json");
  EXPECT_NE(error.find("scene.json: /materials/0/library"), std::string::npos) << error;
  EXPECT_NE(error.find("contact.friction: library 0.2"), std::string::npos) << error;
}

TEST_F(SceneOnLibrary, OtherEffectsThanTheLibrarysAreRefused) {
  write(folder_ / "scene.json", scene_json(R"({"cohesion": false})", ""));
  const std::string error = load_error(folder_ / "scene.json");
  EXPECT_NE(error.find("scene.json: /materials/0"), std::string::npos) << error;
  EXPECT_NE(error.find("built with cohesion on but the scene's effects.cohesion is off"), std::string::npos) << error;
  write(folder_ / "scene.json", scene_json(R"({"rolling_resistance": true})", ""));
  EXPECT_NE(load_error(folder_ / "scene.json").find("rolling_resistance off"), std::string::npos);
}

// The snow cell's dashpots (restitution 0.3) make velocity Verlet unstable below the undamped bound 0.2:
// a Q_t they make unstable is refused with the scene's file, the field and the accepted range.
TEST_F(SceneOnLibrary, ATimeStepFactorTheLibrarysDashpotsMakeUnstableIsRefused) {
  write(folder_ / "scene.json", scene_json("{}", R"(, "substepping": {"q_t": 0.2})"));
  const std::string error = load_error(folder_ / "scene.json");
  EXPECT_NE(error.find("scene.json: /materials/0/substepping/q_t: expected a number in (0, 0.1408"), std::string::npos)
      << error;
  EXPECT_NE(error.find("restitution 0.3"), std::string::npos) << error;
  EXPECT_NE(error.find("got 0.2"), std::string::npos) << error;
  write(folder_ / "scene.json", scene_json("{}", R"(, "substepping": {"q_t": 0.14})"));
  EXPECT_EQ(load_error(folder_ / "scene.json"), "");
}

TEST(Effects, AFrictionlessBoundaryKeepsNoFrictionHistory) {
  for (const double friction : {0.0, 0.5}) {
    Solver solver = elastic_solver(Grid(Vec2(0, 0), 0.1, 6, 6), 1000, 1e5, 0.3);
    solver.add_point(0, Vec2(0.3, 0.13), 0.0025, 0.025, Vec2(0.1, -0.1));
    solver.add_obstacle(Obstacle(Polyline{{Vec2(0, 0.1), Vec2(0.6, 0.1)}, false}, {1e5, 1e5, friction, 0.5}));
    for (int k = 0; k < 3; ++k) solver.step(1e-4);
    EXPECT_EQ(solver.obstacles()[0].tangential_history().size(), friction > 0 ? 1u : 0u);
  }
}

TEST(Effects, NegligibleIncrementsSkipTheConstitutiveCall) {
  // A block at rest next to a sheared one: only the resting points skip, and the sheared ones
  // still get every increment.
  const auto run = [](double skip) {
    SolverSettings settings;
    settings.skip_strain_increment = skip;
    Solver solver(Grid(Vec2(0, 0), 0.1, 12, 6), settings);
    solver.add_law(std::make_unique<ElasticLaw>(1000, Elasticity{1e5, 0.3}));
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) {
        solver.add_point(0, Vec2(0.225 + 0.05 * i, 0.225 + 0.05 * j), 0.0025, 0.025);
        solver.add_point(0, Vec2(0.725 + 0.05 * i, 0.225 + 0.05 * j), 0.0025, 0.025, Vec2(0.5 * (0.05 * j - 0.075), 0));
      }
    for (int k = 0; k < 5; ++k) solver.step(1e-4);
    return solver;
  };
  const Solver reference = run(0), skipping = run(1e-9);
  EXPECT_EQ(reference.skipped_updates(), 0);
  EXPECT_EQ(skipping.skipped_updates(), 16 * 5);
  EXPECT_EQ(skipping.point_updates(), 32 * 5);
  for (std::size_t k = 0; k < reference.points().size(); ++k)
    EXPECT_LE((skipping.points()[k].stress.in_plane - reference.points()[k].stress.in_plane).norm(), 1e-9);
}

}  // namespace
}  // namespace grainbank::mpm
