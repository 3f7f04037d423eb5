// Exact solutions of the discrete scheme: rigid translation, free fall (the MUSL position update
// of a uniform acceleration), and conservation of linear momentum without external forces,
// including next to the grid border (ghost nodes).
#include <gtest/gtest.h>

#include <random>

#include "mpm_solver/core/diagnostics.hpp"
#include "tests/mpm/mpm_test_util.hpp"

namespace grainbank::mpm {
namespace {

using testing::elastic_solver;
using testing::positions_by_id;
using testing::run_until;

TEST(RigidMotion, UniformTranslationIsExactAndStressFree) {
  for (const VelocityTransfer& transfer : {testing::apic(), testing::apic_flip(0), VelocityTransfer{}}) {
    SCOPED_TRACE(testing::describe(transfer));
    Solver solver = elastic_solver(Grid(Vec2(0, 0), 0.1, 20, 10), 1000, 1e6, 0.3, transfer);
    const Vec2 v0(1.0, 0.5);
    seed_region(solver, 0, rectangle(Vec2(0.2, 0.2), Vec2(0.6, 0.5)), 2, v0);
    const auto x0 = positions_by_id(solver);
    run_until(solver, 0.5);
    for (const MaterialPoint& mp : solver.points()) {
      EXPECT_NEAR((mp.position - (x0.at(mp.id) + v0 * solver.time())).norm(), 0, 1e-12);
      EXPECT_NEAR((mp.velocity - v0).norm(), 0, 1e-12);
      EXPECT_NEAR(mp.affine_velocity.norm(), 0, 1e-12);
      EXPECT_NEAR(mp.stress.in_plane.norm(), 0, 1e-6);  // Pa, against E = 1e6 Pa
    }
  }
}

TEST(RigidMotion, FreeFallIsTheExactMuslUpdateOfTheParabola) {
  // Every point moves by the updated velocity, x += Δt (v0 + g t_{n+1}): exactly, and within
  // ½ |g| Δt t of the parabola (the first-order lag of the standard MUSL position update).
  Solver solver = elastic_solver(Grid(Vec2(0, 0), 0.1, 10, 30), 1000, 1e6, 0.3);
  const Vec2 v0(0.2, 2.0), g(0, -9.81);
  solver.set_gravity(Gravity{g, std::nullopt});
  seed_region(solver, 0, rectangle(Vec2(0.3, 2.0), Vec2(0.6, 2.3)), 2, v0);
  const auto x0 = positions_by_id(solver);
  Vec2 shift = Vec2::Zero();
  double previous = 0, max_dt = 0;
  run_until(solver, 0.6, [&](const Solver& s) {
    const double dt = s.time() - previous;
    shift += dt * (v0 + g * s.time());
    previous = s.time();
    max_dt = std::max(max_dt, dt);
  });
  const double t = solver.time();
  for (const MaterialPoint& mp : solver.points()) {
    EXPECT_NEAR((mp.position - (x0.at(mp.id) + shift)).norm(), 0, 1e-11);
    EXPECT_LE((mp.position - (x0.at(mp.id) + v0 * t + 0.5 * g * t * t)).norm(), 0.5 * g.norm() * max_dt * t * (1 + 1e-9));
    EXPECT_NEAR((mp.velocity - (v0 + g * t)).norm(), 0, 1e-11);
  }
}

TEST(RigidMotion, MomentumIsConservedWithoutExternalForcesEvenAtTheGridBorder) {
  // The block fills the first cells of the grid: their stencils reach the ghost ring.
  Solver solver = elastic_solver(Grid(Vec2(0, 0), 0.1, 12, 12), 1000, 1e5, 0.25);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 10; ++i)
      solver.add_point(0, Vec2(0.025 + 0.05 * i, 0.025 + 0.05 * j), 0.0025, 0.025, Vec2(u(rng), u(rng)));
  const FlowMeasures start = measure_flow(solver.points());
  double scale = 0;
  for (const MaterialPoint& mp : solver.points()) scale += mp.mass * mp.velocity.norm();
  run_until(solver, 0.2);
  EXPECT_GT(solver.steps(), 50);
  const FlowMeasures end = measure_flow(solver.points());
  EXPECT_NEAR((end.momentum - start.momentum).norm(), 0, 1e-12 * scale);
  // The elastic block really deformed (stresses are not trivially zero).
  double max_stress = 0;
  for (const MaterialPoint& mp : solver.points()) max_stress = std::max(max_stress, mp.stress.in_plane.norm());
  EXPECT_GT(max_stress, 1e2);
}

}  // namespace
}  // namespace grainbank::mpm
