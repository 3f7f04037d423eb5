// An elastic column (ν = 0, free sides) resting on a frictionless floor under its own weight: once the
// transient is damped out (pure PIC, gravity ramped up), σ_yy = -ρ g (H - y) and σ_xx = 0, where y is
// the initial height of the point above the base (mass per area above it is conserved).
#include <gtest/gtest.h>

#include "tests/mpm/mpm_test_util.hpp"

namespace grainbank::mpm {
namespace {

TEST(ElasticColumn, SelfWeightStressProfile) {
  const double h = 0.05, width = 0.4, height = 1.0, base = 0.1, rho = 1000, g = 9.81;
  Solver solver = testing::elastic_solver(Grid(Vec2(0, 0), h, 12, 24), rho, 5e6, 0.0, testing::pure_pic());
  seed_region(solver, 0, rectangle(Vec2(0.1, base), Vec2(0.1 + width, base + height)), 2);
  solver.add_obstacle(Obstacle(Polyline{{Vec2(-1, base), Vec2(2, base)}, false}, ContactParameters{1e6, 0, 0, 1.0}));
  solver.set_gravity(Gravity{Vec2(0, -g), GravityRamp{Vec2::Zero(), 0.0, 0.3}});
  const auto x0 = testing::positions_by_id(solver);
  testing::run_until(solver, 1.0);
  const double scale = rho * g * height;
  int checked = 0;
  for (const MaterialPoint& mp : solver.points()) {
    const double y = x0.at(mp.id).y() - base;
    // Away from the floor, whose contact forces the splines spread over their support (2 cells), and the top.
    if (y < 3 * h || y > height - 2 * h) continue;
    EXPECT_NEAR(mp.stress.in_plane(1, 1), -rho * g * (height - y), 0.02 * scale) << "point at y = " << y;
    EXPECT_NEAR(mp.stress.in_plane(0, 0), 0.0, 0.02 * scale);
    EXPECT_NEAR(mp.velocity.norm(), 0.0, 1e-3);
    ++checked;
  }
  EXPECT_GT(checked, 400);
}

}  // namespace
}  // namespace grainbank::mpm
