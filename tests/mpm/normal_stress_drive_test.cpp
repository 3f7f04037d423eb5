// The homogeneous drive with σ_yy held (HomogeneousDrive::normal_stress): a law sheared under a
// constant normal stress, as in a rheometer, against the analytic steady state of a frictional cone.
// (Its scene key: homogeneous_live_test.cpp.)
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "mpm_solver/core/solver.hpp"
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

}  // namespace
}  // namespace grainbank::mpm
