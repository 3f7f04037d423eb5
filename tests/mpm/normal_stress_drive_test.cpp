// The homogeneous drive with σ_yy held (HomogeneousDrive::normal_stress): a law sheared under a
// constant normal stress, as in a rheometer, against the analytic steady state of a frictional cone.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "common/temporary_directory.hpp"
#include "mpm_solver/core/solver.hpp"
#include "mpm_solver/io/scene_input.hpp"
#include "mpm_solver/laws/drucker_prager_law.hpp"

namespace grainbank::mpm {
namespace {

// A cohesionless Drucker–Prager point without dilatancy in steady simple shear under σ_yy = −P: its
// plastic flow is the deviatoric direction of D, pure xy shear, so every normal deviator vanishes,
// p = P and sqrt(J2) = |σ_xy|, and the cone sqrt(J2) = sin φ p gives σ_xy / P = sin φ. The volume
// stops changing (L_yy → 0) once the point flows.
TEST(NormalStressDrive, AFrictionalConeShearsAtItsFrictionUnderTheHeldNormalStress) {
  const double phi = 30 * std::numbers::pi / 180, pressure = 1000, rate = 1, dt = 1e-4;
  DruckerPragerParameters parameters;
  parameters.elasticity = Elasticity{1e6, 0.3};
  parameters.friction_angle = phi;
  Solver solver(Grid(Vec2(0, 0), 0.1, 8, 8), SolverSettings{});
  solver.add_law(std::make_unique<DruckerPragerLaw>(1500, parameters));
  const Vec2 centre(0.4, 0.4);
  solver.add_point(0, centre, 1e-2, 0.05);
  Mat2 L = Mat2::Zero();
  L(0, 1) = rate;
  solver.set_homogeneous_drive(HomogeneousDrive{L, centre, NormalStressControl{pressure, 1.0, 0.05}});
  for (int k = 0; k < 3000; ++k) solver.step(dt);  // a shear strain of 0.3
  const MaterialPoint& point = solver.points()[0];
  const double volume = point.volume;
  for (int k = 0; k < 1000; ++k) solver.step(dt);
  const PointStress& s = solver.points()[0].stress;
  EXPECT_NEAR(s.in_plane(1, 1), -pressure, 1e-3 * pressure);
  // The spin turns some shear stress into normal deviators at every step, which the radial return
  // scales back but does not remove: of order σ_xy² / G, 0.07 % of P here.
  EXPECT_NEAR(s.in_plane(0, 0), -pressure, 5e-3 * pressure);
  EXPECT_NEAR(s.zz, -pressure, 5e-3 * pressure);
  EXPECT_NEAR(std::abs(s.in_plane(0, 1)) / pressure, std::sin(phi), 5e-3);
  EXPECT_NEAR(solver.points()[0].volume / volume, 1.0, 1e-4) << "a cone without dilatancy keeps its volume in flow";
}

TEST(NormalStressDrive, TheSceneKeyIsReadAndBadValuesAreRefusedByName) {
  const TemporaryDirectory folder("normal-stress-scene");
  auto scene = [](const std::string& drive) {
    return R"({"grid": {"origin": [0, 0], "cell_size": 0.1, "cells": [10, 10]},
      "time": {"end": 0.01, "output_interval": 0.01},
      "integration": {"transfer": "pic", "homogeneous_drive": )" + drive + R"(},
      "materials": [{"name": "a", "law": "elastic", "density": 1000, "young": 1e6, "poisson": 0.3}],
      "regions": [{"material": "a", "rectangle": {"min": [0.3, 0.3], "max": [0.6, 0.5]}, "points_per_cell": 2}]})";
  };
  const io::Scene s = io::load_scene(folder.write(
      "scene.json", scene(R"({"L": [[0, 2], [0, 0]], "normal_stress": {"stress": 500, "response_rate": 3}})")));
  const auto& control = s.solver->settings().homogeneous_drive->normal_stress;
  ASSERT_TRUE(control.has_value());
  EXPECT_EQ(control->stress, 500);
  EXPECT_EQ(control->response_rate, 3);

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
