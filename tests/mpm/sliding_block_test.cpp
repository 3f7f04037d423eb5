// An elastic block sliding down a fixed inclined line obstacle with Coulomb friction: once sliding,
// its centre of mass accelerates along the slope at a = g (sin θ - μ cos θ).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "tests/mpm/mpm_test_util.hpp"

namespace grainbank::mpm {
namespace {

TEST(SlidingBlock, AccelerationOnAnInclinedFrictionalLine) {
  const double theta = std::numbers::pi / 6, mu = 0.2, g = 9.81;
  const Vec2 down(std::cos(theta), -std::sin(theta)), up_normal(std::sin(theta), std::cos(theta));
  const Vec2 top(0.1, 1.2);
  Solver solver = testing::elastic_solver(Grid(Vec2(0, 0.6), 0.025, 40, 32), 1000, 1e7, 0.3);
  solver.add_obstacle(Obstacle(Polyline{{top, top + 2.5 * down}, false}, ContactParameters{1e6, 1e6, mu, 0.5}));
  solver.set_gravity(Gravity{Vec2(0, -g), std::nullopt});
  // Lifted by one disk radius (0.00625 m) so that no point starts overlapping the line.
  const Vec2 corner = top + 0.1 * down + 0.0063 * up_normal;
  seed_region(solver, 0,
              Polyline{{corner, corner + 0.3 * down, corner + 0.3 * down + 0.1 * up_normal, corner + 0.1 * up_normal},
                       true},
              2);
  // Least-squares slope of the centre-of-mass velocity along the slope over [0.15, 0.45] s.
  double st = 0, sv = 0, stt = 0, stv = 0;
  int n = 0;
  testing::run_until(solver, 0.45, [&](const Solver& s) {
    if (s.time() < 0.15) return;
    double mass = 0, momentum = 0;
    for (const MaterialPoint& mp : s.points()) mass += mp.mass, momentum += mp.mass * mp.velocity.dot(down);
    const double v = momentum / mass, t = s.time();
    st += t, sv += v, stt += t * t, stv += t * v, ++n;
  });
  const double a = (n * stv - st * sv) / (n * stt - st * st);
  const double expected = g * (std::sin(theta) - mu * std::cos(theta));
  EXPECT_NEAR(a, expected, 0.02 * expected);
}

}  // namespace
}  // namespace grainbank::mpm
