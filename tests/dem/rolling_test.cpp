// Rolling resistance: a rolling spring between neighbours, capped by μ_r R_ij f_n, with no twisting
// resistance, turning with the contact frame. Tests on a ring of four spheres pressed together along x,
// without tangential stiffness, so that only the rolling law acts on the spins.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "tests/dem/dem_test_util.hpp"

namespace grainbank::dem::test {
namespace {

constexpr double kRadius = 0.5e-3;

Material rolling_material(double k_r, double mu_r, double density = 2650) {
  Material m = small_material();
  m.density = density;
  m.contact.k_t = 0;  // no tangential force: the spins feel the rolling moments alone
  m.contact.friction = 0;
  m.effects.rolling = true;
  m.rolling = {k_r, mu_r};
  return m;
}

// Four equal spheres in a ring along x (periodic pitch 2R - δ): each touches both neighbours with the
// overlap δ, so the ring rests in equilibrium under the normal forces k_n δ. Spins alternate ±w.
DemCell ring(const Material& m, double overlap, const Vec3& w) {
  const double a = 2 * kRadius - overlap;
  std::vector<Vec3> x;
  for (int k = 0; k < 4; ++k) x.emplace_back((k + 0.5) * a, 5 * kRadius, 5 * kRadius);
  const Mat3 h = Vec3(4 * a, 10 * kRadius, 10 * kRadius).asDiagonal();
  return DemCell(fresh_state(h, x, std::vector<double>(4, kRadius), {}, {w, -w, w, -w}), m, 0.1 * kRadius);
}

// Relative rolling of neighbours at ±Ω about z ⟂ n, optionally with a twist ±Ω_t about n = x. Once the
// moment reaches its cap μ_r R_ij f_n (R_ij = R/2, f_n = k_n δ), each sphere feels two capped moments
// against its rolling spin: I dω_z/dt = -2 μ_r R_ij f_n, a constant deceleration. Returns the measured
// deceleration of sphere 0 over most of the way to the stop and checks the cap and the moment's
// direction (⟂ n) at every step, and the twist spin, which nothing resists.
struct RollingRun {
  double measured = 0, expected = 0;
};
RollingRun decelerate(double twist_spin) {
  const double overlap = 2e-6, k_r = 1e-3, mu_r = 0.01, omega = 1e3;
  const Material mat = rolling_material(k_r, mu_r);
  DemCell cell = ring(mat, overlap, Vec3(twist_spin, 0, omega));
  EXPECT_EQ(cell.contact_count(), 4u) << "test design: a closed ring";
  const double inertia = 0.4 * sphere_mass(mat, kRadius) * kRadius * kRadius;
  const double cap = mu_r * 0.5 * kRadius * mat.contact.k_n * overlap;
  RollingRun run;
  run.expected = 2 * cap / inertia;
  const double dt = cell.time_step(0.1), stop = omega / run.expected;
  EXPECT_GT(stop / dt, 50) << "test design: many steps to the stop";
  EXPECT_GT(k_r * 2 * omega * dt, cap) << "test design: the moment is capped from the first step";
  const long n1 = 10, n2 = static_cast<long>(0.8 * stop / dt), n_end = static_cast<long>(2 * stop / dt);
  double w1 = 0, largest = 0, largest_along_n = 0, twist_change = 0;
  for (long k = 1; k <= n_end; ++k) {
    cell.step_with_velocity_gradient(Mat3::Zero(), dt);
    const CellState st = cell.state();
    for (const Vec3& m : st.rolling_moment) {
      largest = std::max(largest, m.norm());
      largest_along_n = std::max(largest_along_n, std::abs(m.x()));
    }
    twist_change = std::max(twist_change, std::abs(st.angular_velocity[0].x() - twist_spin));
    if (k == n1) w1 = st.angular_velocity[0].z();
    if (k == n2) run.measured = (w1 - st.angular_velocity[0].z()) / (static_cast<double>(n2 - n1) * dt);
  }
  EXPECT_LE(largest, cap * (1 + 1e-12)) << "the cap μ_r R_ij f_n";
  EXPECT_LE(largest_along_n, 1e-12 * cap) << "a rolling moment has no component along n";
  EXPECT_EQ(twist_change, 0) << "twisting is not resisted";
  // Stopped: the springs, at most at their cap, hold the spins in an elastic oscillation whose energy
  // is that of four springs at the cap plus one step's worth of rolling: 4·½ I ω² ≤ 4·cap²/(2 k_r) + ...
  const double bound = std::sqrt(cap * cap / (k_r * inertia) + std::pow(run.expected * dt, 2));
  EXPECT_LT(std::abs(cell.state().angular_velocity[0].z()), 1.05 * bound) << "Ω was " << omega;
  return run;
}

TEST(RollingResistance, RelativeRollingDeceleratesAtTheCappedMomentAndStops) {
  const RollingRun run = decelerate(0);
  EXPECT_NEAR(run.measured, run.expected, 1e-9 * run.expected);
}

TEST(RollingResistance, TwistAboutTheNormalIsNeitherResistedNorTakenFromTheRollingCap) {
  // The model has no twisting law: a twist about n keeps its spin, and the rolling moment keeps its
  // whole cap (capping rolling and twisting together would slow the rolling by 1/√2 here).
  const RollingRun run = decelerate(1e3);
  EXPECT_NEAR(run.measured, run.expected, 1e-9 * run.expected);
}

// Heavy spheres (slow rolling oscillation) with elastic rolling moments about y, then at rest without
// spin of their own; the cell is turned rigidly by `angle` about `axis`.
void expect_moments_turn_with_pairs(const Vec3& axis, double angle) {
  const Material mat = rolling_material(1e-3, 10, 2650e9);
  DemCell loading = ring(mat, 2e-6, Vec3(0, 1e-2, 0));
  const double dt = loading.time_step(0.1);
  for (int k = 0; k < 10; ++k) loading.step_with_velocity_gradient(Mat3::Zero(), dt);
  CellState st = loading.state();
  st.angular_velocity.assign(4, Vec3::Zero());
  DemCell cell(std::move(st), mat, loading.skin());
  const std::vector<Vec3> m0 = cell.state().rolling_moment;
  ASSERT_EQ(m0.size(), 4u);
  for (const Vec3& m : m0) ASSERT_GT(m.norm(), 1e-6) << "test design: loaded rolling springs";
  const double rate = 1e3;
  const int increments = 1000;
  Substepping q;
  q.q_n = 10;
  const Mat3 inc = Eigen::AngleAxisd(angle / increments, axis).toRotationMatrix();
  for (int k = 0; k < increments; ++k) cell.advance(inc, angle / increments / rate, q);
  const Mat3 r = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
  const std::vector<Vec3> m = cell.state().rolling_moment;
  for (std::size_t k = 0; k < m0.size(); ++k)
    EXPECT_LT((m[k] - r * m0[k]).norm(), 1e-3 * m0[k].norm())
        << "pair " << k << ": M before " << m0[k].transpose() << ", after " << m[k].transpose() << ", expected "
        << (r * m0[k]).transpose();
}

TEST(RollingResistance, RollingMomentTurnsWithTheContactNormal) {
  // The ring turns rigidly about z: every contact normal turns, the rolling moments must turn with
  // them and no new moment may load (the spins are the cell's, no relative rotation).
  expect_moments_turn_with_pairs(Vec3::UnitZ(), std::numbers::pi / 6);
}

TEST(RollingResistance, RollingMomentTurnsWithThePairsTwist) {
  // The ring turns rigidly about its contact normals x: the moments about y must turn about x.
  expect_moments_turn_with_pairs(Vec3::UnitX(), std::numbers::pi / 2);
}

}  // namespace
}  // namespace grainbank::dem::test
