// Numerical hard cases of the periodic cell: loadings far from the quasi-static, small-strain
// regime. Each test asserts finite results and a physical invariant or bound (sign of the shear
// stress, friction-bounded stress ratio, exact F and volume, zero stress without contacts, no lost
// contacts), never numbers copied from a run.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "dem_sampler/cell/overlap_warning.hpp"
#include "tests/dem/dem_test_util.hpp"

namespace grainbank::dem::test {
namespace {

// The same spheres rebuilt from scratch: its Verlet list is built anew, so its contact count is
// the true one, whatever history the driven cell's list carries.
std::size_t contacts_from_scratch(const DemCell& c) {
  const CellState st = c.state();
  return DemCell(fresh_state(st.h, c.positions(), st.radius, st.velocity, st.angular_velocity), c.material(), c.skin())
      .contact_count();
}

bool all_finite(const DemCell& c) {
  for (const Vec3& x : c.positions())
    if (!x.allFinite()) return false;
  for (const Vec3& v : c.velocities())
    if (!v.allFinite()) return false;
  const CellMeasures m = c.measures();
  return m.stress.allFinite() && std::isfinite(m.kinetic_energy) && std::isfinite(m.unbalanced_force_ratio);
}

double mean_diameter(const DemCell& c) {
  double sum = 0;
  for (double r : c.radii()) sum += 2 * r;
  return sum / static_cast<double>(c.size());
}

TEST(HardCases, ShearAtImpactRateInertialNumberOneStaysFiniteWithFrictionBoundedStressRatio) {
  // I = γ̇ d / sqrt(p0/ρ) = 1: collisional flow. The cell must stay finite, resist with σ_xy of
  // the sign of γ̇, and keep a stress ratio |σ_xy|/p of the order of a granular flow's (μ(I) ≤ ~1).
  const Material mat = small_material();
  const DemCell prepared = prepare_cell(mat, small_spec(64, 21));
  const double p0 = pressure_of(prepared.measures().stress);
  const double rate = 1.0 / (mean_diameter(prepared) * std::sqrt(mat.density / p0));
  DemCell cell = prepared;
  const double duration = 1e-5;
  IncrementResult res;
  for (int k = 0; k < 50; ++k) {  // γ ≈ 1
    res = cell.advance(simple_shear(rate * duration), duration, Substepping{});
    ASSERT_TRUE(res.stress.allFinite() && all_finite(cell)) << "increment " << k;
    ASSERT_LE(res.substep, cell.time_step(0.1) * (1 + 1e-12));
  }
  const double p = pressure_of(res.stress);
  std::printf("γ̇ = %.0f 1/s: p = %.3g Pa (p0 %.3g), σ_xy/p = %.3f, E_kin = %.3g J\n", rate, p, p0,
              res.stress(0, 1) / p, cell.measures().kinetic_energy);
  EXPECT_GT(p, 0) << "a sheared packing at constant volume stays in compression";
  EXPECT_GT(res.stress(0, 1), 0.05 * p);
  EXPECT_LT(res.stress(0, 1), 1.5 * p);
  EXPECT_GT(cell.measures().kinetic_energy, 0);
  EXPECT_NEAR(cell.volume(), prepared.volume(), 1e-12 * prepared.volume());
  EXPECT_EQ(cell.contact_count(), contacts_from_scratch(cell));
}

TEST(HardCases, SimpleShearToGammaTenFlipsTheCellRepeatedlyAndKeepsEveryContact) {
  // γ = 10 tilts the cell by ten cell heights: only repeated flips to a reduced basis keep it
  // thick enough. F stays exactly the imposed simple shear and the volume exactly constant.
  const Material mat = small_material();
  DemCell cell = prepare_cell(mat, small_spec(64, 13));
  const double v0 = cell.volume(), rate = 200, duration = 1e-3;
  const int increments = 50;
  IncrementResult res;
  for (int k = 0; k < increments; ++k) {
    res = cell.advance(simple_shear(rate * duration), duration, Substepping{});
    ASSERT_TRUE(res.stress.allFinite() && all_finite(cell)) << "increment " << k;
    ASSERT_FALSE(needs_reduction(cell.cell_matrix())) << "increment " << k;
  }
  const double gamma = rate * duration * increments;
  ASSERT_GE(gamma, 10);
  // The tilt passes one half once per unit of shear strain.
  EXPECT_GE(cell.flips(), static_cast<std::int64_t>(gamma) - 1);
  EXPECT_LT((cell.deformation_gradient() - simple_shear(gamma)).cwiseAbs().maxCoeff(), 1e-10);
  EXPECT_NEAR(cell.volume(), v0, 1e-11 * v0);
  const double p = pressure_of(res.stress);
  EXPECT_GT(p, 0);
  EXPECT_GT(res.stress(0, 1), 0.05 * p);
  EXPECT_LT(res.stress(0, 1), p) << "stress ratio above 1 is unphysical for μ = 0.5 in slow shear";
  EXPECT_EQ(cell.contact_count(), contacts_from_scratch(cell)) << "a contact was lost across the flips";
}

TEST(HardCases, TensionToCompleteSeparationLeavesNoContactAndExactlyZeroStress) {
  // Isotropic expansion of a cohesionless packing until the spheres are a dilute gas: no pair
  // touches any more, so the Love–Weber sum is empty and σ = 0 exactly (kinetic stress is off).
  const Material mat = small_material();
  DemCell cell = prepare_cell(mat, small_spec(64, 17));
  ASSERT_GT(cell.contact_count(), 64u);
  const double rate = 50, duration = 1e-3;
  const Mat3 stretch = std::exp(rate * duration) * Mat3::Identity();
  for (int k = 0; k < 20; ++k) {  // linear stretch e^1: φ falls by e^3
    const IncrementResult res = cell.advance(stretch, duration, Substepping{});
    ASSERT_TRUE(res.stress.allFinite() && all_finite(cell)) << "increment " << k;
  }
  const CellMeasures m = cell.measures();
  EXPECT_EQ(cell.contact_count(), 0u);
  EXPECT_EQ(contacts_from_scratch(cell), 0u);
  EXPECT_EQ(m.stress, Mat3::Zero());
  EXPECT_EQ(m.coordination, 0);
  EXPECT_LT(m.solid_fraction, 0.05);
  EXPECT_TRUE(std::isfinite(m.kinetic_energy));
}

TEST(HardCases, AllBondsBreakingInOneIncrementGiveFullDamageAndFiniteState) {
  // A bonded packing stretched by 10 % in one increment of 1 µs (two DEM steps): every bond is
  // stretched ~10× past its tensile limit T_0 / (w_b k_n), too fast for its force to drag the
  // spheres along, and breaks within that increment. Damage jumps to 1, the state
  // stays finite, and once the fragments separate the stress is zero.
  const Material mat = small_material(true);
  DemCell cell = prepare_cell(mat, small_spec(64, 19));
  const std::int64_t bonds0 = cell.measures().bonds;
  ASSERT_GT(bonds0, 64);
  const double limit_stretch = mat.bond.tensile_strength / ((1 - mat.contact.contact_weight) * mat.contact.k_n);
  ASSERT_GT(0.1 * mean_diameter(cell), 5 * limit_stretch);
  const IncrementResult res = cell.advance(1.1 * Mat3::Identity(), 1e-6, Substepping{});
  const CellMeasures m = cell.measures();
  EXPECT_EQ(m.bonds, 0);
  EXPECT_EQ(m.damage, 1.0);
  EXPECT_TRUE(res.stress.allFinite());
  EXPECT_TRUE(all_finite(cell));
  const Mat3 stretch = std::exp(50 * 1e-3) * Mat3::Identity();
  for (int k = 0; k < 20; ++k) ASSERT_NO_THROW(cell.advance(stretch, 1e-3, Substepping{})) << "increment " << k;
  EXPECT_EQ(cell.contact_count(), 0u);
  EXPECT_EQ(cell.measures().stress, Mat3::Zero());
}

TEST(HardCases, VeryHighPressureWarnsOfLargeOverlapsAndKeepsTheSeedTimeStep) {
  // k_n / (p d) = 5: overlaps of several per cent. The linear contact law stays stable (the step of
  // seed Eq. 3 does not depend on overlap) so the cell shears finitely, but a warning names the
  // overlap and the remedy. The same material at low pressure gives no warning.
  const Material mat = small_material();
  PreparationSpec spec = small_spec(64, 23);
  spec.pressure = 2e7;
  const DemCell prepared = prepare_cell(mat, spec);
  const CellMeasures m0 = prepared.measures();
  EXPECT_NEAR(pressure_of(m0.stress), spec.pressure, 0.05 * spec.pressure);
  EXPECT_GT(prepared.max_overlap(), kLargeOverlap);
  EXPECT_LT(prepared.max_overlap(), 0.5) << "spheres must not pass through each other";
  const auto warning = large_overlap_warning(prepared);
  ASSERT_TRUE(warning.has_value());
  EXPECT_NE(warning->find("large overlaps"), std::string::npos) << *warning;
  EXPECT_NE(warning->find("k_n"), std::string::npos) << *warning;

  DemCell cell = prepared;
  const double dt_seed = cell.time_step(0.1);
  for (int k = 0; k < 20; ++k) {
    const IncrementResult res = cell.advance(simple_shear(0.01), 1e-3, Substepping{});
    ASSERT_TRUE(res.stress.allFinite() && all_finite(cell)) << "increment " << k;
    ASSERT_LE(res.substep, dt_seed * (1 + 1e-12)) << "sub-step above seed Eq. 3";
    ASSERT_EQ(res.substeps, substep_count(1e-3, dt_seed, 1));
  }
  const double p = pressure_of(cell.measures().stress);
  EXPECT_GT(p, 0.5 * spec.pressure);
  EXPECT_LT(p, 3 * spec.pressure);
  EXPECT_LT(cell.max_overlap(), 0.5);

  const DemCell gentle = prepare_cell(mat, small_spec(64, 23));
  EXPECT_LT(gentle.max_overlap(), kLargeOverlap);
  EXPECT_FALSE(large_overlap_warning(gentle).has_value());
}

TEST(HardCases, APressureNoContactCanHoldStopsWithAMessageNotACrash) {
  // 1e308 Pa: the servo crushes the cell in its first steps until its matrix is no longer finite.
  // Before the check a non-finite cell indexed the Verlet bins out of range (a segmentation fault).
  PreparationSpec spec = small_spec(32, 23);
  spec.pressure = 1e308;
  try {
    prepare_cell(small_material(), spec);
    FAIL() << "a cell prepared at 1e308 Pa";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("DEM cell diverged"), std::string::npos) << what;
    EXPECT_NE(what.find("lower Q_t, the strain rate or the target stress"), std::string::npos) << what;
  }
  // The same packing at a pressure its contacts hold prepares.
  spec.pressure = 1e4;
  EXPECT_TRUE(all_finite(prepare_cell(small_material(), spec)));
}

TEST(HardCases, RadiusRatioOneToFivePacksShearsAndKeepsEveryContact) {
  // Diameters uniform in [0.4, 2] mm: the lightest sphere (125× lighter than the heaviest) sets the
  // step, the largest the neighbour range. Preparation still converges, shear stays finite and
  // bounded, and the Verlet list holds every small-large contact.
  const Material mat = small_material();
  PreparationSpec spec = small_spec(64, 29);
  spec.min_diameter = 0.4e-3;
  spec.max_diameter = 2.0e-3;
  PreparationReport report;
  DemCell cell = prepare_cell(mat, spec, &report);
  const auto [rmin, rmax] = std::minmax_element(cell.radii().begin(), cell.radii().end());
  std::printf("radius ratio %.2f, phi %.3f, Z %.2f\n", *rmax / *rmin, report.final.solid_fraction,
              report.final.coordination);
  ASSERT_GT(*rmax / *rmin, 4.0);
  EXPECT_NEAR(pressure_of(report.final.stress), spec.pressure, 2 * spec.pressure_tolerance * spec.pressure);
  EXPECT_NEAR(cell.time_step(0.1),
              dem_time_step(0.1, sphere_mass(mat, *rmin), *rmin, mat.contact.k_n, mat.contact.k_t, 0), 1e-18);
  EXPECT_LT(cell.max_overlap(), kLargeOverlap);
  IncrementResult res;
  for (int k = 0; k < 30; ++k) {  // γ = 0.6, through a flip
    res = cell.advance(simple_shear(0.02), 1e-4, Substepping{});
    ASSERT_TRUE(res.stress.allFinite() && all_finite(cell)) << "increment " << k;
  }
  EXPECT_GE(cell.flips(), 1);
  const double p = pressure_of(res.stress);
  EXPECT_GT(p, 0);
  EXPECT_GT(res.stress(0, 1), 0);
  EXPECT_LT(res.stress(0, 1), 1.5 * p);
  EXPECT_LT(cell.max_overlap(), 0.25) << "a small sphere must not pass into a large one";
  EXPECT_EQ(cell.contact_count(), contacts_from_scratch(cell));
}

}  // namespace
}  // namespace grainbank::dem::test
