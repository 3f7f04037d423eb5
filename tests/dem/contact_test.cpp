// Frictional visco-elastic contact (seed Fig. 1 a, b) checked on isolated two-sphere collisions:
// restitution coefficient, energy, momentum and angular momentum; seed Eq. 3 time step; kinetic stress.
#include <gtest/gtest.h>

#include "tests/dem/dem_test_util.hpp"

namespace grainbank::dem::test {
namespace {

constexpr double kCell = 20e-3;  // a large cubic cell: the pair never meets a periodic image

struct Collision {
  double approach_speed = 0, separation_speed = 0;
  double energy_before = 0, energy_after = 0;
  Vec3 momentum_before, momentum_after;
  Vec3 angular_momentum_before, angular_momentum_after;
  bool touched = false;
  long contact_steps = 0;
};

// Total angular momentum about the origin: orbital Σ x × m v plus spin Σ I ω.
Vec3 angular_momentum(const DemCell& c) {
  const CellState st = c.state();
  const std::vector<Vec3> x = c.positions();
  Vec3 l = Vec3::Zero();
  for (std::size_t p = 0; p < c.size(); ++p) {
    const double m = sphere_mass(c.material(), st.radius[p]);
    l += x[p].cross(m * st.velocity[p]) + 0.4 * m * st.radius[p] * st.radius[p] * st.angular_velocity[p];
  }
  return l;
}

Vec3 momentum(const DemCell& c) {
  const CellState st = c.state();
  Vec3 q = Vec3::Zero();
  for (std::size_t p = 0; p < c.size(); ++p) q += sphere_mass(c.material(), st.radius[p]) * st.velocity[p];
  return q;
}

// Two spheres approaching along `dir` (unit) with relative speed `speed`, an optional tangential
// relative velocity and spins; zero total momentum. Runs until they have separated again.
Collision collide(const Material& mat, double r0, double r1, const Vec3& dir, double speed,
                  const Vec3& tangential = Vec3::Zero(), const Vec3& spin0 = Vec3::Zero(), double q_t = 0.002) {
  const double m0 = sphere_mass(mat, r0), m1 = sphere_mass(mat, r1);
  const Vec3 centre = Vec3::Constant(0.5 * kCell);
  const double gap0 = 2e-6;
  const Vec3 x0 = centre - 0.5 * (r0 + r1 + gap0) * dir, x1 = centre + 0.5 * (r0 + r1 + gap0) * dir;
  const Vec3 vrel = -speed * dir + tangential;  // velocity of 1 relative to 0
  const Vec3 v0 = -m1 / (m0 + m1) * vrel, v1 = m0 / (m0 + m1) * vrel;
  DemCell cell(fresh_state(kCell * Mat3::Identity(), {x0, x1}, {r0, r1}, {v0, v1}, {spin0, Vec3::Zero()}), mat,
               0.1e-3);
  Collision out;
  out.approach_speed = -(v1 - v0).dot(dir);
  out.energy_before = cell.measures().kinetic_energy;
  out.momentum_before = momentum(cell);
  out.angular_momentum_before = angular_momentum(cell);
  const double dt = cell.time_step(q_t);
  for (long step = 0; step < 2'000'000; ++step) {
    cell.step_with_velocity_gradient(Mat3::Zero(), dt);
    const bool touching = cell.contact_count() > 0;
    if (touching) {
      out.touched = true;
      ++out.contact_steps;
    }
    if (out.touched && !touching) break;
  }
  const std::vector<Vec3> x = cell.positions();
  const Vec3 n = (x[1] - x[0]).normalized();
  const CellState st = cell.state();
  out.separation_speed = (st.velocity[1] - st.velocity[0]).dot(n);
  out.energy_after = cell.measures().kinetic_energy;
  out.momentum_after = momentum(cell);
  out.angular_momentum_after = angular_momentum(cell);
  return out;
}

Material collision_material(double restitution, double friction = 0) {
  Material m = small_material();
  m.contact.restitution = restitution;
  m.contact.friction = friction;
  m.contact.contact_weight = 1;
  return m;
}

TEST(TwoSphereCollision, HeadOnRestitutionMatchesCoefficient) {
  const Vec3 dir = Vec3(1, 2, -0.5).normalized();
  for (double e : {0.3, 0.5, 0.8}) {
    const Collision c = collide(collision_material(e), 0.5e-3, 0.5e-3, dir, 0.1);
    ASSERT_TRUE(c.touched);
    EXPECT_GT(c.contact_steps, 100) << "time step too coarse for a 1% check";
    EXPECT_NEAR(c.separation_speed / c.approach_speed, e, 0.01 * e) << "e_n = " << e;
    // The energy lost is exactly the (1 - e²) of the normal relative motion (head on, no spin).
    EXPECT_NEAR(c.energy_after / c.energy_before, e * e, 0.02 * e * e);
  }
}

TEST(TwoSphereCollision, UnequalSpheresUseReducedMassInDashpot) {
  // The dashpot c_n = 2ζ sqrt(m_ij k_n) must use the reduced mass m_ij = m_i m_j / (m_i + m_j):
  // then e_n does not depend on the size ratio.
  const Vec3 dir = Vec3(0.3, -1, 0.2).normalized();
  for (double ratio : {1.5, 3.0}) {
    const Collision c = collide(collision_material(0.5), 0.4e-3, 0.4e-3 * ratio, dir, 0.05);
    ASSERT_TRUE(c.touched);
    EXPECT_NEAR(c.separation_speed / c.approach_speed, 0.5, 0.005) << "radius ratio " << ratio;
  }
}

TEST(TwoSphereCollision, ElasticCollisionConservesEnergy) {
  const Vec3 dir = Vec3(-1, 0.4, 0.7).normalized();
  const Collision c = collide(collision_material(1.0), 0.45e-3, 0.55e-3, dir, 0.2);
  ASSERT_TRUE(c.touched);
  EXPECT_NEAR(c.energy_after, c.energy_before, 1e-3 * c.energy_before);
  EXPECT_NEAR(c.separation_speed, c.approach_speed, 1e-3 * c.approach_speed);
  EXPECT_LT((c.momentum_after - c.momentum_before).norm(), 1e-12 * sphere_mass(small_material(), 0.5e-3) * 0.2);
}

TEST(TwoSphereCollision, ObliqueFrictionalCollisionConservesMomentaAndDissipates) {
  // Oblique impact with sliding friction and an initial spin: linear momentum is conserved exactly
  // (action = reaction), angular momentum up to the overlap/radius lever-arm error of DEM, and
  // friction plus damping can only dissipate.
  const Vec3 dir = Vec3(1, 0.2, 0.1).normalized();
  const Vec3 tangential = 0.05 * dir.cross(Vec3::UnitZ()).normalized();
  const Collision c = collide(collision_material(0.7, 0.5), 0.5e-3, 0.6e-3, dir, 0.1, tangential, Vec3(100, -200, 300));
  ASSERT_TRUE(c.touched);
  ASSERT_GT(c.angular_momentum_before.norm(), 1e-11) << "test design: a non-trivial angular momentum";
  const double p_scale = sphere_mass(small_material(), 0.5e-3) * 0.1;
  EXPECT_LT((c.momentum_after - c.momentum_before).norm(), 1e-12 * p_scale);
  EXPECT_LT((c.angular_momentum_after - c.angular_momentum_before).norm(),
            1e-3 * c.angular_momentum_before.norm());
  EXPECT_LT(c.energy_after, c.energy_before);
  EXPECT_GT(c.energy_after, 0);
}

TEST(TwoSphereCollision, GrazingSpheresStayOutOfContact) {
  // Spheres that pass each other with a clearance never interact: velocities unchanged.
  const Material mat = collision_material(0.5, 0.5);
  const double r = 0.5e-3;
  const Vec3 c = Vec3::Constant(0.5 * kCell);
  const Vec3 x0 = c + Vec3(-2e-3, -(r + 1e-6), 0), x1 = c + Vec3(2e-3, r + 1e-6, 0);
  const Vec3 v0(0.1, 0, 0), v1(-0.1, 0, 0);
  DemCell cell(fresh_state(kCell * Mat3::Identity(), {x0, x1}, {r, r}, {v0, v1}), mat, 0.1e-3);
  const double dt = cell.time_step(0.05);
  for (int k = 0; k < static_cast<int>(4e-3 / 0.2 / dt) + 10; ++k) cell.step_with_velocity_gradient(Mat3::Zero(), dt);
  EXPECT_EQ(cell.velocities()[0], v0);
  EXPECT_EQ(cell.velocities()[1], v1);
  EXPECT_GT(cell.positions()[0].x(), cell.positions()[1].x()) << "the spheres should have passed each other";
}

TEST(TimeStep, SeedEquation3ForStiffestModeOfLightestSphere) {
  // δt = Q_t π sqrt(m_min / k_max), m_min from the smallest radius R and the density, k_max the
  // stiffest mode of that sphere (I = 2/5 m R²): normal k_n; tangential k_t (1 + m R²/I) = 3.5 k_t, as
  // the spring at the contact point moves centre and spin together; rolling, δt = Q_t π sqrt(I / k_r).
  const std::vector<double> r = {0.6e-3, 0.41e-3, 0.5e-3};
  const std::vector<Vec3> x = {Vec3(1e-3, 1e-3, 1e-3), Vec3(4e-3, 4e-3, 4e-3), Vec3(7e-3, 7e-3, 7e-3)};
  const double m_min = 2650 * 4.0 / 3.0 * std::numbers::pi * std::pow(0.41e-3, 3);
  const double i_min = 0.4 * m_min * 0.41e-3 * 0.41e-3;
  auto step = [&](const Material& mat, double q) {
    return DemCell(fresh_state(10e-3 * Mat3::Identity(), x, r), mat, 0.1e-3).time_step(q);
  };
  Material mat = small_material();
  for (double q : {0.05, 0.1, 0.2}) {
    mat.contact.k_t = 0.2e5;  // 3.5 k_t < k_n: the normal mode is the stiffest
    EXPECT_NEAR(step(mat, q), q * std::numbers::pi * std::sqrt(m_min / 1e5), 1e-14 * step(mat, q));
    mat.contact.k_t = 0.5e5;  // 3.5 k_t > k_n: the tangential-rotational mode is
    EXPECT_NEAR(step(mat, q), q * std::numbers::pi * std::sqrt(m_min / (3.5 * 0.5e5)), 1e-14 * step(mat, q));
    mat.effects.rolling = true;
    mat.rolling = {0.1, 0.1};  // k_r / I far above 3.5 k_t / m: the rolling mode is
    EXPECT_NEAR(step(mat, q), q * std::numbers::pi * std::sqrt(i_min / 0.1), 1e-14 * step(mat, q));
    mat.effects.rolling = false;
  }
}

TEST(KineticStress, DiluteGasGivesMinusSumOfMvvOverVolume) {
  // Seed Eq. 2, kinetic term only: σ = -(1/V) Σ m v'⊗v' (tension-positive: a gas pushes outward).
  Material mat = small_material();
  mat.effects.kinetic_stress = true;
  const double side = 10e-3;
  std::vector<Vec3> x, v;
  std::vector<double> r;
  for (int k = 0; k < 8; ++k) {
    x.emplace_back((k & 1 ? 2.5 : 7.5) * 1e-3, (k & 2 ? 2.5 : 7.5) * 1e-3, (k & 4 ? 2.5 : 7.5) * 1e-3);
    v.emplace_back(0.01 * (k - 3.5), 0.02 * std::sin(k), -0.015 * std::cos(2 * k));
    r.push_back(0.4e-3 + 0.02e-3 * k);
  }
  DemCell cell(fresh_state(side * Mat3::Identity(), x, r, v), mat, 0.1e-3);
  cell.step_with_velocity_gradient(Mat3::Zero(), 1e-7);  // no forces: velocities stay as given
  Mat3 expected = Mat3::Zero();
  for (int k = 0; k < 8; ++k) expected -= sphere_mass(mat, r[k]) * v[k] * v[k].transpose();
  expected /= side * side * side;
  EXPECT_LT(rel_diff(cell.measures().stress, expected), 1e-12);
  EXPECT_LT(cell.measures().stress.trace(), 0) << "kinetic stress must be compressive";

  Material off = mat;
  off.effects.kinetic_stress = false;
  DemCell quiet(fresh_state(side * Mat3::Identity(), x, r, v), off, 0.1e-3);
  quiet.step_with_velocity_gradient(Mat3::Zero(), 1e-7);
  EXPECT_EQ(quiet.measures().stress, Mat3::Zero()) << "kinetic term must be absent when the effect is off";
}

}  // namespace
}  // namespace grainbank::dem::test
