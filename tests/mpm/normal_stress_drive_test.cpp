// The homogeneous drive with σ_yy held (HomogeneousDrive::normal_stress): a law sheared under a
// constant normal stress, as in a rheometer, against the analytic steady state of a frictional cone.
// (Its scene key: homogeneous_live_test.cpp.)
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>

#include "mpm_solver/core/solver.hpp"
#include "mpm_solver/io/restart.hpp"
#include "mpm_solver/laws/drucker_prager_law.hpp"

namespace grainbank::mpm {
namespace {

constexpr double kPressure = 1000, kDt = 1e-4;
const Vec2 kCentre(0.4, 0.4);

// One cohesionless Drucker–Prager point (φ = 30°) in simple shear at 1 /s under σ_yy = −1 kPa.
Solver sheared_cone() {
  DruckerPragerParameters parameters;
  parameters.elasticity = Elasticity{1e6, 0.3};
  parameters.friction_angle = 30 * std::numbers::pi / 180;
  Solver solver(Grid(Vec2(0, 0), 0.1, 8, 8), SolverSettings{});
  solver.add_law(std::make_unique<DruckerPragerLaw>(1500, parameters));
  solver.add_point(0, kCentre, 1e-2, 0.05);
  Mat2 L = Mat2::Zero();
  L(0, 1) = 1;
  solver.set_homogeneous_drive(HomogeneousDrive{L, kCentre, NormalStressControl{kPressure, 1.0, 0.05}});
  return solver;
}

// A cohesionless Drucker–Prager point without dilatancy in steady simple shear under σ_yy = −P: its
// plastic flow is the deviatoric direction of D, pure xy shear, so every normal deviator vanishes,
// p = P and sqrt(J2) = |σ_xy|, and the cone sqrt(J2) = sin φ p gives σ_xy / P = sin φ. The volume
// stops changing (L_yy → 0) once the point flows.
TEST(NormalStressDrive, AFrictionalConeShearsAtItsFrictionUnderTheHeldNormalStress) {
  const double phi = 30 * std::numbers::pi / 180, pressure = kPressure;
  Solver solver = sheared_cone();
  for (int k = 0; k < 3000; ++k) solver.step(kDt);  // a shear strain of 0.3
  const double volume = solver.points()[0].volume;
  for (int k = 0; k < 1000; ++k) solver.step(kDt);
  const PointStress& s = solver.points()[0].stress;
  EXPECT_NEAR(s.in_plane(1, 1), -pressure, 1e-3 * pressure);
  // The spin turns some shear stress into normal deviators at every step, which the radial return
  // scales back but does not remove: of order σ_xy² / G, 0.07 % of P here (0.13 % measured).
  EXPECT_NEAR(s.in_plane(0, 0), -pressure, 5e-3 * pressure);
  EXPECT_NEAR(s.zz, -pressure, 5e-3 * pressure);
  EXPECT_NEAR(std::abs(s.in_plane(0, 1)) / pressure, std::sin(phi), 5e-3);
  EXPECT_NEAR(solver.points()[0].volume / volume, 1.0, 1e-4) << "a cone without dilatancy keeps its volume in flow";
}

// The servo's integral is state: a run restarted halfway goes on as the uninterrupted one, to the bit.
TEST(NormalStressDrive, ARestartContinuesTheServoExactly) {
  Solver reference = sheared_cone();
  for (int k = 0; k < 400; ++k) reference.step(kDt);
  Solver first = sheared_cone();
  for (int k = 0; k < 200; ++k) first.step(kDt);
  ASSERT_NE(first.drive_integral(), 0);
  const auto file = std::filesystem::temp_directory_path() / "grainbank-normal-stress-restart.h5";
  std::filesystem::remove(file);
  io::write_restart(file, first);
  Solver resumed = sheared_cone();
  io::read_restart(file, resumed);
  std::filesystem::remove(file);
  EXPECT_EQ(resumed.drive_integral(), first.drive_integral());
  for (int k = 0; k < 200; ++k) resumed.step(kDt);
  EXPECT_EQ(resumed.points()[0].stress.in_plane, reference.points()[0].stress.in_plane);
  EXPECT_EQ(resumed.points()[0].volume, reference.points()[0].volume);
}

}  // namespace
}  // namespace grainbank::mpm
