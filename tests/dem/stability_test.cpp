// Stability of velocity Verlet at the largest accepted time-step factor Q_t (seed Eq. 3 over the
// stiffest mode, see dem_time_step, lowered by the contact dashpots: max_time_step_factor), on dense
// bonded packings.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "tests/dem/dem_test_util.hpp"

namespace grainbank::dem::test {
namespace {

struct Perturbed {
  double kinetic_growth;  // largest kinetic energy over the run, relative to the initial one
  long bonds_broken;
};

// A prepared packing with small random velocities and spins (every mode excited), run `steps` steps
// at Q_t with no drive; without `dashpots`, its pairs' and the material's normal dashpots are removed.
// Stops early once the kinetic energy exceeds 1e3 times its initial value.
Perturbed perturb(const DemCell& prepared, double q_t, long steps, bool dashpots = true) {
  CellState st = prepared.state();
  Material material = prepared.material();
  if (!dashpots) {
    material.contact.restitution = 1;
    for (Pair& pair : st.pairs) pair.damping = 0;
  }
  std::mt19937_64 rng(7);
  std::normal_distribution<double> g(0, 1e-4);
  for (Vec3& v : st.velocity) v = Vec3(g(rng), g(rng), g(rng));                  // [m/s]
  for (Vec3& w : st.angular_velocity) w = Vec3(g(rng), g(rng), g(rng)) / 0.5e-3;  // [rad/s]
  DemCell cell(std::move(st), material, prepared.skin());
  const double k0 = cell.measures().kinetic_energy, dt = cell.time_step(q_t);
  double largest = k0;
  for (long k = 0; k < steps && largest < 1e3 * k0; ++k) {
    cell.step_with_velocity_gradient(Mat3::Zero(), dt);
    const double kinetic = cell.measures().kinetic_energy;
    largest = std::isfinite(kinetic) ? std::max(largest, kinetic) : 1e300;
  }
  return {largest / k0, static_cast<long>(prepared.measures().bonds) - static_cast<long>(cell.measures().bonds)};
}

// A dense bonded packing (Z ≈ 8): tangential stiffness k_t = `tangential` k_n.
Material dense_bonded_material(double tangential, double restitution, double contact_weight) {
  Material mat = small_material(true);
  mat.contact.k_t = tangential * mat.contact.k_n;
  mat.contact.restitution = restitution;
  mat.contact.contact_weight = contact_weight;
  mat.bond.bonding_distance = 0.15;
  return mat;
}

TEST(Stability, DenseBondedPackingStaysStableAtTheLargestAcceptedQt) {
  // The tangential-rotational mode stiffer than the normal one (3.5 k_t > k_n), no dashpot to hide a
  // growing mode, bonds carrying most of the stiffness.
  const DemCell prepared = prepare_cell(dense_bonded_material(1, 1, 0.2), small_spec(125, 5));
  ASSERT_GT(prepared.measures().coordination, 7.5) << "test design: a dense bonded packing";
  ASSERT_EQ(max_time_step_factor(1), kMaxTimeStepFactor);
  // Undamped and elastic, the perturbation's energy is shared between springs and motion: the kinetic
  // energy stays below its initial value up to the integration error.
  const Perturbed at_bound = perturb(prepared, kMaxTimeStepFactor, 20000);
  EXPECT_LT(at_bound.kinetic_growth, 1.1);
  EXPECT_EQ(at_bound.bonds_broken, 0);
  // The test can fail: 1.5 times the bound blows up within the same run.
  EXPECT_GT(perturb(prepared, 1.5 * kMaxTimeStepFactor, 20000).kinetic_growth, 100)
      << "test design: a stiff enough packing";
}

// Velocity Verlet sees a dashpot at the half-step velocity, which lowers its stable step to
// ω δt < 2 (√(1 + ζ²) − ζ). One packing whose normal mode sets the step (k_t = 0.2 k_n), restitution
// 0.1 (ζ = 0.59): without its dashpots it holds at the undamped bound 0.2; with them it blows up there,
// and holds at its own accepted bound, 0.114.
TEST(Stability, DashpotsLowerTheStableStepAndTheAcceptedBoundFollows) {
  const DemCell prepared = prepare_cell(dense_bonded_material(0.2, 0.1, 0.5), small_spec(125, 5));
  ASSERT_GT(prepared.measures().coordination, 7.5) << "test design: a dense bonded packing";
  const Perturbed undamped = perturb(prepared, kMaxTimeStepFactor, 20000, false);
  EXPECT_LT(undamped.kinetic_growth, 1.1) << "test design: without its dashpots the packing is stable at 0.2";
  EXPECT_EQ(undamped.bonds_broken, 0);
  EXPECT_GT(perturb(prepared, kMaxTimeStepFactor, 20000).kinetic_growth, 100);
  const double bound = max_time_step_factor(0.1);
  EXPECT_NEAR(bound, 0.114, 0.001);
  const Perturbed at_bound = perturb(prepared, bound, 20000);
  EXPECT_LT(at_bound.kinetic_growth, 1.1);
  EXPECT_EQ(at_bound.bonds_broken, 0);
}

TEST(Stability, QtAboveTheBoundIsRefusedNamingTheFieldAndTheRange) {
  DemCell cell = prepare_cell(small_material(true), small_spec(27, 5));
  Substepping q;
  q.q_t = 0.25;
  try {
    cell.advance(Mat3::Identity(), 1e-4, q);
    FAIL() << "Q_t = 0.25 accepted";
  } catch (const std::invalid_argument& e) {
    // small_material's restitution 0.5 (ζ = 0.215) lowers the bound 0.2 by the factor 0.808.
    EXPECT_NE(std::string(e.what()).find("substepping.q_t: expected a number in (0, 0.161"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("restitution 0.5"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("got 0.25"), std::string::npos) << e.what();
  }
  PreparationSpec spec = small_spec(27, 5);
  spec.q_t = 0.25;
  EXPECT_THROW(prepare_cell(small_material(true), spec), std::invalid_argument);
}

}  // namespace
}  // namespace grainbank::dem::test
