// Energy balance of a driven cell. The engine keeps no energy tally (adding one would cost the force
// loop a branch or a template instantiation per effect), so the test tallies from the cell's
// public state: the work of the cell deformation W = ∫ V σ : L dt (σ with its kinetic term,
// unsymmetrised), the kinetic energy K and the elastic energy U of the contact springs computed
// here from positions, radii and tangential forces.
//  - elastic cell (no friction, restitution 1, no bonds): W = ΔK + ΔU closes to the integration
//    error of velocity Verlet;
//  - damped frictional cell: W - ΔK - ΔU is the energy dissipated by dashpots and sliding, which
//    must be positive (it cannot be tallied separately here, only bounded).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "tests/dem/dem_test_util.hpp"

namespace grainbank::dem::test {
namespace {

// Σ over touching pairs of ½ w_c k_n d_n² + |f_t|² / (2 w_c k_t): the contact springs' energy.
double elastic_energy(const DemCell& c) {
  const CellState st = c.state();
  const std::vector<Vec3> x = c.positions();
  const ContactLaw& law = c.material().contact;
  const double kn = law.contact_weight * law.k_n, kt = law.contact_weight * law.k_t;
  double u = 0;
  for (const Pair& p : st.pairs) {
    const Vec3 l = x[p.j] - x[p.i] + st.h * shift_vector(static_cast<int>(p.image)).cast<double>();
    const double gap = l.norm() - st.radius[p.i] - st.radius[p.j];
    if (gap >= 0) continue;
    u += 0.5 * kn * gap * gap;
    if (kt > 0) u += 0.5 * p.ft.squaredNorm() / kt;
  }
  return u;
}

struct Balance {
  double work = 0, delta_kinetic = 0, delta_elastic = 0;
  double residual() const { return work - delta_kinetic - delta_elastic; }
};

// Drives the cell at the velocity gradient L for `steps` DEM steps of the seed-Eq.-3 step,
// integrating the power V σ : L (trapezoidal rule, L of each step from its actual Δh).
Balance drive(DemCell& cell, const Mat3& L, int steps, double q_t = 0.1) {
  Balance b;
  const double k0 = cell.measures().kinetic_energy, u0 = elastic_energy(cell);
  const double dt = cell.time_step(q_t);
  for (int k = 0; k < steps; ++k) {
    const Mat3 h0 = cell.cell_matrix();
    const Mat3 power_density0 = cell.volume() * cell.measures().stress;
    cell.step_with_velocity_gradient(L, dt);
    // A flip changes h by an integer basis change, not by deformation.
    EXPECT_EQ(cell.flips(), 0);
    const Mat3 h1 = cell.cell_matrix();
    const Mat3 step_gradient = (h1 - h0) * (0.5 * (h0 + h1)).inverse();
    const Mat3 mean = 0.5 * (power_density0 + cell.volume() * cell.measures().stress);
    b.work += (mean.cwiseProduct(step_gradient)).sum();
  }
  b.delta_kinetic = cell.measures().kinetic_energy - k0;
  b.delta_elastic = elastic_energy(cell) - u0;
  return b;
}

// Compression with shear and rotation: work goes into both springs and fluctuations.
const Mat3 kCompression = (Mat3() << -20, 30, 0,  //
                           -10, -15, 0,           //
                           0, 0, -10).finished();  // [1/s]

TEST(EnergyBalance, ElasticFrictionlessUndampedCellStoresExactlyTheWorkOfItsDeformation) {
  Material mat = small_material();
  mat.contact.friction = 0;
  mat.contact.restitution = 1;
  mat.effects.kinetic_stress = true;  // V σ : L then includes the work exchanged with fluctuations
  // The same deformation (3000 steps at Q_t = 0.1 of seed Eq. 3) with steps twice and four times
  // smaller: the residual is the integration error (velocity Verlet and the trapezoidal work). The
  // trajectories are chaotic and differ with the step, so one packing's residuals need not shrink
  // (over packing seeds 31-38 the full-to-quarter-step ratio ranged from 1.3 to 65); the order is
  // judged on the median over five packings: second order gives 16, first order 4.
  // Without dissipation the packing never comes to rest once the preparation's damping is off, so the
  // preparation's equilibrium check is off: only the work balance from this state is tested.
  PreparationSpec spec = small_spec(64, 0);
  spec.equilibrium_hold = 0;
  std::vector<double> ratios;
  for (std::uint64_t seed : {31, 32, 33, 34, 35}) {
    spec.seed = seed;
    const DemCell prepared = prepare_cell(mat, spec);
    double residual[3];
    for (int k = 0; k < 3; ++k) {
      const int refine = 1 << k;
      DemCell cell = prepared;
      const Balance b = drive(cell, kCompression, 3000 * refine, 0.1 / refine);
      residual[k] = std::abs(b.residual()) / b.work;
      std::printf("seed %llu, Q_t = %.3f: W = %.4e J, dK = %.4e J, dU = %.4e J, |W - dK - dU| / W = %.2e\n",
                  static_cast<unsigned long long>(seed), 0.1 / refine, b.work, b.delta_kinetic, b.delta_elastic,
                  residual[k]);
      ASSERT_GT(b.work, 0);
      // The fluctuations must take a share of the work (2.8-30 % over these seeds) far above the
      // residuals checked below (at most 1.8e-3 measured).
      EXPECT_GT(b.delta_kinetic, 0.02 * b.work) << "the drive must agitate the spheres, not only load springs";
    }
    EXPECT_LT(residual[0], 2e-2);
    EXPECT_LT(residual[1], 1e-3);
    EXPECT_LT(residual[2], 1e-3);
    ratios.push_back(residual[0] / residual[2]);
  }
  std::nth_element(ratios.begin(), ratios.begin() + 2, ratios.end());
  EXPECT_GT(ratios[2], 4) << "the median residual must shrink faster than first order";
}

TEST(EnergyBalance, DampedFrictionalCellDissipatesAPositiveShareOfTheWork) {
  Material mat = small_material();  // μ = 0.5, e_n = 0.5
  mat.effects.kinetic_stress = true;
  DemCell cell = prepare_cell(mat, small_spec(64, 31));
  const Mat3 shear = (Mat3() << 0, 100, 0, 0, 0, 0, 0, 0, 0).finished();  // γ = 0.25, no flip
  const Balance b = drive(cell, shear, 3000);
  std::printf("W = %.4e J, dK = %.4e J, dU = %.4e J, dissipated %.4e J\n", b.work, b.delta_kinetic, b.delta_elastic,
              b.residual());
  ASSERT_GT(b.work, 0);
  EXPECT_GT(b.residual(), 0.1 * b.work) << "dashpots and sliding must dissipate";
  EXPECT_LT(b.residual(), b.work + cell.measures().kinetic_energy + elastic_energy(cell))
      << "more dissipated than the energy there was";
}

}  // namespace
}  // namespace grainbank::dem::test
