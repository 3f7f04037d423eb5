// Stability of velocity Verlet at the largest accepted time-step factor Q_t (seed Eq. 3 over the
// stiffest mode, see dem_time_step), on a dense bonded packing whose tangential-rotational mode is
// stiffer than its normal one (k_t = k_n: 3.5 k_t > k_n).
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "tests/dem/dem_test_util.hpp"

namespace grainbank::dem::test {
namespace {

// Largest kinetic energy over `steps` undamped steps at Q_t, relative to the initial one: a prepared
// packing with small random velocities and spins (every mode excited). Stops early once it exceeds 1e3.
double kinetic_growth(const DemCell& prepared, double q_t, long steps) {
  CellState st = prepared.state();
  std::mt19937_64 rng(7);
  std::normal_distribution<double> g(0, 1e-4);
  for (Vec3& v : st.velocity) v = Vec3(g(rng), g(rng), g(rng));                  // [m/s]
  for (Vec3& w : st.angular_velocity) w = Vec3(g(rng), g(rng), g(rng)) / 0.5e-3;  // [rad/s]
  DemCell cell(std::move(st), prepared.material(), prepared.skin());
  const double k0 = cell.measures().kinetic_energy, dt = cell.time_step(q_t);
  double largest = k0;
  for (long k = 0; k < steps && largest < 1e3 * k0; ++k) {
    cell.step_with_velocity_gradient(Mat3::Zero(), dt);
    const double kinetic = cell.measures().kinetic_energy;
    largest = std::isfinite(kinetic) ? std::max(largest, kinetic) : 1e300;
  }
  EXPECT_EQ(cell.measures().bonds, prepared.measures().bonds) << "Q_t = " << q_t << ": the perturbation breaks no bond";
  return largest / k0;
}

TEST(Stability, DenseBondedPackingStaysStableAtTheLargestAcceptedQt) {
  Material mat = small_material(true);
  mat.contact.k_t = mat.contact.k_n;
  mat.contact.restitution = 1;           // no dashpot to hide a growing mode
  mat.contact.contact_weight = 0.2;      // bonds carry most of the stiffness
  mat.bond.bonding_distance = 0.15;      // many bonds: Z ≈ 8
  const DemCell prepared = prepare_cell(mat, small_spec(125, 5));
  ASSERT_GT(prepared.measures().coordination, 7.5) << "test design: a dense bonded packing";
  // Undamped and elastic, the perturbation's energy is shared between springs and motion: the kinetic
  // energy stays below its initial value up to the integration error.
  EXPECT_LT(kinetic_growth(prepared, kMaxTimeStepFactor, 20000), 1.1);
  // The test can fail: 1.5 times the bound blows up within the same run.
  EXPECT_GT(kinetic_growth(prepared, 1.5 * kMaxTimeStepFactor, 20000), 100) << "test design: a stiff enough packing";
}

TEST(Stability, QtAboveTheBoundIsRefusedNamingTheFieldAndTheRange) {
  DemCell cell = prepare_cell(small_material(true), small_spec(27, 5));
  Substepping q;
  q.q_t = 0.25;
  try {
    cell.advance(Mat3::Identity(), 1e-4, q);
    FAIL() << "Q_t = 0.25 accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("substepping.q_t: expected a number in (0, 0.2]"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("got 0.25"), std::string::npos) << e.what();
  }
  PreparationSpec spec = small_spec(27, 5);
  spec.q_t = 0.25;
  EXPECT_THROW(prepare_cell(small_material(true), spec), std::invalid_argument);
}

}  // namespace
}  // namespace grainbank::dem::test
