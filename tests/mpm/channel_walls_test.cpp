// Side walls of a channel (mpm_solver/core/channel_walls.hpp), on an elastic block sliding over a
// frictionless base: by the momentum balance, the walls take from it, per unit mass,
//   c = (2 μ_w / W) Σ_p V_p max(0, −σ_zz,p) / Σ_p m_p
// against its motion while it slides, and nothing more; they hold it when its drive stays below c.
// Laterally free and in plane strain, the block carries σ_zz = ν σ_yy, and in the continuum
// σ_yy = −ρ g cos θ (d − y) over its depth d: c = μ_w ν g cos θ d / W. Four cells deep, the MPM
// block's Σ V σ_yy is 12 % below that (its weight is carried at its bottom row of points), so the
// balance is checked against the stress the points carry, and the continuum's c within 15 %.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <optional>

#include "tests/mpm/mpm_test_util.hpp"

namespace grainbank::mpm {
namespace {

constexpr double kDensity = 1000, kYoung = 1e7, kPoisson = 0.3, kG = 9.81, kDepth = 0.1, kLength = 0.3;
constexpr double kCell = 0.025;

// An elastic block kLength × kDepth, 2 × 2 points per cell, resting on a frictionless line through
// `corner` along `along` (unit), moving along it at `speed`, between walls `walls` (none if empty).
Solver block_on_a_line(const Vec2& corner, const Vec2& along, double speed, std::optional<ChannelWalls> walls) {
  SolverSettings settings = testing::settings_with(VelocityTransfer{});
  settings.channel_walls = walls;
  Solver solver(Grid(Vec2(-0.1, -0.6), kCell, 60, 32), settings);
  solver.add_law(std::make_unique<ElasticLaw>(kDensity, Elasticity{kYoung, kPoisson}));
  const Vec2 normal(-along.y(), along.x());
  solver.add_obstacle(Obstacle(Polyline{{corner - 0.5 * along, corner + 2 * along}, false},
                               ContactParameters{1e6, 1e6, 0.0, 0.5}));
  const double spacing = kCell / 2, radius = spacing / 2;
  for (int j = 0; j < static_cast<int>(std::lround(kDepth / spacing)); ++j)
    for (int i = 0; i < static_cast<int>(std::lround(kLength / spacing)); ++i)
      solver.add_point(0, corner + (i + 0.5) * spacing * along + ((j + 0.5) * spacing + 0.01 * radius) * normal,
                       spacing * spacing, radius, speed * along);
  solver.set_gravity(Gravity{Vec2(0, -kG), std::nullopt});
  return solver;
}

// Centre-of-mass displacement and velocity along `along`.
struct Motion {
  double displacement, velocity;
};
Motion motion_along(const Solver& s, const Vec2& along, const Vec2& start) {
  double mass = 0, x = 0, v = 0;
  for (const MaterialPoint& mp : s.points()) {
    mass += mp.mass;
    x += mp.mass * mp.position.dot(along);
    v += mp.mass * mp.velocity.dot(along);
  }
  return {x / mass - start.dot(along), v / mass};
}
Vec2 centre(const Solver& s) {
  Vec2 c = Vec2::Zero();
  double mass = 0;
  for (const MaterialPoint& mp : s.points()) c += mp.mass * mp.position, mass += mp.mass;
  return c / mass;
}

// c above, from the stress the points carry.
double wall_friction_per_mass(const Solver& s, const ChannelWalls& walls) {
  double force = 0, mass = 0;
  for (const MaterialPoint& mp : s.points()) force += mp.volume * walls.friction_per_volume(mp.stress), mass += mp.mass;
  return force / mass;
}
// c of the continuum.
double continuum_wall_friction_per_mass(const ChannelWalls& walls, double slope) {
  return walls.friction * kPoisson * kG * std::cos(slope) * kDepth / walls.width;
}

TEST(ChannelWalls, ABlockSlidingBetweenThemLosesTheirFrictionAndStopsForGood) {
  const double v0 = 0.3;
  const Vec2 along(1, 0);
  const ChannelWalls walls(0.05, 0.5);  // c ≈ 2.9 m/s²: the block stops after about 0.1 s
  Solver solver = block_on_a_line(Vec2(0, 0), along, v0, walls);
  const Vec2 start = centre(solver);
  double taken = 0, c_sum = 0, largest_back = 0, velocity_mid = 0;
  int n = 0;
  testing::run_until(solver, 0.3, [&](const Solver& s) {
    const double v = motion_along(s, along, start).velocity;
    if (s.time() <= 0.05 + 1e-12) {
      const double c = wall_friction_per_mass(s, walls);
      taken += c * std::min(s.stable_time_step(), 0.05 - s.time());  // what the next step's walls take
      c_sum += c, ++n;
      velocity_mid = v;
    }
    if (s.time() > 0.15) largest_back = std::max(largest_back, -v);
  });
  EXPECT_NEAR(velocity_mid, v0 - taken, 0.02 * v0);
  EXPECT_NEAR(c_sum / n, continuum_wall_friction_per_mass(walls, 0), 0.15 * continuum_wall_friction_per_mass(walls, 0));
  EXPECT_LT(std::abs(motion_along(solver, along, start).velocity), 1e-3 * v0);
  EXPECT_LT(largest_back, 1e-3 * v0);  // friction never drives it backwards

  Solver free = block_on_a_line(Vec2(0, 0), along, v0, std::nullopt);
  const Vec2 free_start = centre(free);
  testing::run_until(free, 0.3);
  EXPECT_NEAR(motion_along(free, along, free_start).displacement, 0.3 * v0, 0.01 * 0.3 * v0);
}

TEST(ChannelWalls, HoldABlockOnASlopeBelowTheirFrictionAndSlowItAbove) {
  const double slope = 10 * std::numbers::pi / 180;
  const Vec2 down(std::cos(slope), -std::sin(slope));
  const double drive = kG * std::sin(slope);  // 1.70 m/s² on the frictionless slope
  const ChannelWalls narrow(0.05, 0.5), wide(0.2, 0.5);
  ASSERT_GT(0.85 * continuum_wall_friction_per_mass(narrow, slope), 1.4 * drive);  // 2.90 m/s²: held
  ASSERT_LT(continuum_wall_friction_per_mass(wide, slope), 0.5 * drive);           // 0.72 m/s²: slides
  Solver held = block_on_a_line(Vec2(0, 0), down, 0, narrow);
  const Vec2 held_start = centre(held);
  testing::run_until(held, 0.3);
  EXPECT_LT(std::abs(motion_along(held, down, held_start).displacement), 1e-3);

  // Least squares of the velocity over [0.1, 0.3] s against the drive less the walls' mean take.
  Solver sliding = block_on_a_line(Vec2(0, 0), down, 0, wide);
  const Vec2 start = centre(sliding);
  double st = 0, sv = 0, stt = 0, stv = 0, c_sum = 0;
  int n = 0;
  testing::run_until(sliding, 0.3, [&](const Solver& s) {
    if (s.time() < 0.1) return;
    const double v = motion_along(s, down, start).velocity, t = s.time();
    st += t, sv += v, stt += t * t, stv += t * v, c_sum += wall_friction_per_mass(s, wide), ++n;
  });
  const double expected = drive - c_sum / n;
  EXPECT_NEAR((n * stv - st * sv) / (n * stt - st * st), expected, 0.02 * expected);
}

}  // namespace
}  // namespace grainbank::mpm
