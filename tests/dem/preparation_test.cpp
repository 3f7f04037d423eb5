// Cell preparation (seeded, reproducible), bit-identical state round trips, effects that are off
// cost nothing, and the sign of the shear stress of a prepared frictional cell.
#include <gtest/gtest.h>

#include "tests/dem/dem_test_util.hpp"

namespace grainbank::dem::test {
namespace {

TEST(Preparation, ReachesTargetPressureInEquilibrium) {
  const Material mat = small_material();
  const PreparationSpec spec = small_spec(100, 21);
  PreparationReport report;
  const DemCell cell = prepare_cell(mat, spec, &report);
  const CellMeasures m = cell.measures();
  EXPECT_NEAR(pressure_of(m.stress), spec.pressure, spec.pressure_tolerance * spec.pressure);
  EXPECT_LT(m.unbalanced_force_ratio, spec.unbalanced_force_tolerance);
  EXPECT_GT(report.compression_steps, 0);
  EXPECT_EQ(cell.time(), 0.0) << "a template starts at t = 0";
  EXPECT_LT((cell.deformation_gradient() - Mat3::Identity()).cwiseAbs().maxCoeff(), 1e-15) << "a template starts at F = I";
  // Independent check of the pressure: rebuilt from the positions alone (no tangential history,
  // spheres at rest), the trace of the Love-Weber sum only involves the elastic normal forces.
  const DemCell geometric = DemCell::from_packing(cell.cell_matrix(), cell.positions(), cell.radii(), mat, cell.skin());
  EXPECT_NEAR(pressure_of(geometric.measures().stress), spec.pressure, (spec.pressure_tolerance + 0.01) * spec.pressure);
  // A dense random packing of frictional spheres, isotropic: φ in the usual range, no shear stress.
  EXPECT_GT(m.solid_fraction, 0.55);
  EXPECT_LT(m.solid_fraction, 0.66);
  EXPECT_GT(m.coordination, 3.5);
  EXPECT_LT(std::abs(m.stress(0, 1)), 0.1 * spec.pressure);
  // The prepared template is at rest: kinetic energy negligible against the elastic energy scale
  // p_0 d³ per sphere.
  EXPECT_LT(m.kinetic_energy, 1e-3 * static_cast<double>(cell.size()) * spec.pressure * 1e-9);
}

// The template is promised to be in equilibrium without the preparation's damping and servo: stepped
// alone at fixed volume for the check's hold, its pressure stays near p_0.
TEST(Preparation, TemplateLeftAloneHoldsItsPressure) {
  const Material mat = small_material();
  const PreparationSpec spec = small_spec(100, 22);
  DemCell cell = prepare_cell(mat, spec);
  const double hold = equilibrium_hold_seconds(mat, spec);
  const double dt = cell.time_step(spec.q_t);
  for (double t = 0; t < hold; t += dt) cell.step_with_velocity_gradient(Mat3::Zero(), dt);
  EXPECT_NEAR(pressure_of(cell.measures().stress), spec.pressure,
              (spec.pressure_tolerance + spec.equilibrium_drift) * spec.pressure);
}

// Frictionless spheres need Z = 6 contacts each to be rigid (isostatic counting); a packing jammed
// with friction has fewer, so with its friction taken away it must collapse, and the check sees it.
TEST(Preparation, CheckSeesAHypostaticPackingCollapse) {
  const Material mat = small_material();
  PreparationSpec spec = small_spec(100, 23);
  spec.compression_friction = mat.contact.friction;  // jammed loose
  const double hold = equilibrium_hold_seconds(mat, spec);
  spec.equilibrium_hold = 0;                         // the check off: the loose template as prepared
  DemCell cell = prepare_cell(mat, spec);
  ASSERT_LT(cell.measures().coordination, 5.5);
  cell.set_friction(0);
  EXPECT_GT(pressure_drift_at_rest(cell, hold, spec.q_t, spec.pressure), 0.3);
}

TEST(Preparation, RefusesATemplateThatDriftsAtRestNamingTheField) {
  PreparationSpec spec = small_spec(60, 24);
  spec.equilibrium_drift = 1e-9;  // any real packing moves more than this as its last imbalance rings out
  try {
    prepare_cell(small_material(), spec);
    ADD_FAILURE() << "expected the equilibrium check to refuse the template";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("not in equilibrium"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("preparation.equilibrium_drift: expected at most"), std::string::npos)
        << e.what();
  }
}

TEST(Preparation, RadiiFollowRequestedUniformDiameterRange) {
  const Material mat = small_material();
  const PreparationSpec spec = small_spec(125, 22);
  const DemCell cell = prepare_cell(mat, spec);
  ASSERT_EQ(cell.size(), 125u);
  double sum = 0, lo = 1, hi = 0;
  for (double r : cell.radii()) {
    EXPECT_GE(2 * r, spec.min_diameter);
    EXPECT_LE(2 * r, spec.max_diameter);
    sum += 2 * r;
    lo = std::min(lo, 2 * r);
    hi = std::max(hi, 2 * r);
  }
  // Uniform diameters: mean (min+max)/2, standard error (max-min)/sqrt(12 N); 4.5 standard errors.
  const double mean = sum / 125, se = (spec.max_diameter - spec.min_diameter) / std::sqrt(12.0 * 125);
  EXPECT_NEAR(mean, 0.5 * (spec.min_diameter + spec.max_diameter), 4.5 * se);
  // The whole range is used (P(all above 0.9 mm) = 0.75^125).
  EXPECT_LT(lo, 0.9e-3);
  EXPECT_GT(hi, 1.1e-3);
}

TEST(Preparation, SameSeedGivesBitIdenticalCellDifferentSeedDoesNot) {
  const Material mat = small_material(true);
  const DemCell a = prepare_cell(mat, small_spec(64, 5));
  const DemCell b = prepare_cell(mat, small_spec(64, 5));
  std::string why;
  EXPECT_TRUE(states_identical(a.state(), b.state(), &why)) << "differs in " << why;
  const DemCell c = prepare_cell(mat, small_spec(64, 6));
  EXPECT_NE(a.radii(), c.radii());
  EXPECT_FALSE(states_identical(a.state(), c.state()));
  EXPECT_GT(a.measures().bonds, 0) << "bonded preparation should create bonds";
}

TEST(StateRoundTrip, RebuiltCellContinuesBitIdentically) {
  // DemCell(cell.state(), material, skin) is the same cell: driven alike, both stay bit-identical,
  // through shear (with a flip), stretch, bond breakage and a round trip in mid-run.
  Material mat = small_material(true);
  mat.bond.tensile_strength = 2e-3;  // weak enough that shearing breaks some bonds
  mat.bond.shear_strength = 2e-3;
  DemCell original = prepare_cell(mat, small_spec(64, 7));
  DemCell copy(original.state(), original.material(), original.skin());
  Substepping q;
  q.q_n = 20;
  const double duration = 2e-4;
  Mat3 shear = Mat3::Identity();
  shear(0, 1) = 0.02;
  Mat3 stretch = Mat3::Identity();
  stretch(1, 1) = 1.001;
  std::string why;
  for (int k = 0; k < 40; ++k) {
    const Mat3& f = k % 4 == 3 ? stretch : shear;
    const IncrementResult r1 = original.advance(f, duration, q);
    const IncrementResult r2 = copy.advance(f, duration, q);
    ASSERT_EQ(r1.stress, r2.stress) << "increment " << k;
    ASSERT_TRUE(states_identical(original.state(), copy.state(), &why)) << "increment " << k << ": " << why;
    if (k == 20) copy = DemCell(copy.state(), mat, copy.skin());  // round trip in mid-run
  }
  EXPECT_GT(original.flips(), 0) << "test design: the shear should have flipped the cell";
  EXPECT_GT(original.measures().damage, 0) << "test design: some bonds should have broken";
  EXPECT_EQ(original.measures().stress, copy.measures().stress);
}

TEST(StateRoundTrip, StepWithVelocityGradientAfterRoundTripIsIdentical) {
  DemCell original = prepare_cell(small_material(), small_spec(64, 8));
  Mat3 l = Mat3::Zero();
  l(0, 1) = 5;
  l(2, 2) = -1;
  const double dt = original.time_step(0.1);
  for (int k = 0; k < 500; ++k) original.step_with_velocity_gradient(l, dt);
  DemCell copy(original.state(), original.material(), original.skin());
  for (int k = 0; k < 2000; ++k) {
    original.step_with_velocity_gradient(l, dt);
    copy.step_with_velocity_gradient(l, dt);
  }
  std::string why;
  EXPECT_TRUE(states_identical(original.state(), copy.state(), &why)) << why;
}

TEST(Effects, SwitchedOffEffectsHoldNoArrays) {
  // Bonds and rolling off: no bond or rolling arrays at all; on: one entry per Verlet pair.
  const PreparationSpec spec = small_spec(64, 9);
  const DemCell plain = random_gas(small_material(), spec);
  EXPECT_GT(plain.pair_count(), 0u);
  EXPECT_TRUE(plain.state().bonds.empty());
  EXPECT_TRUE(plain.state().rolling_moment.empty());
  EXPECT_EQ(plain.measures().bonds, 0);
  EXPECT_EQ(plain.measures().damage, 0);

  Material rolling = small_material();
  rolling.effects.rolling = true;
  rolling.rolling.stiffness = 1e-4;
  rolling.rolling.friction = 0.1;
  const DemCell r = random_gas(rolling, spec);
  EXPECT_TRUE(r.state().bonds.empty());
  EXPECT_EQ(r.state().rolling_moment.size(), r.pair_count());

  const DemCell b = random_gas(small_material(true), spec);
  EXPECT_EQ(b.state().bonds.size(), b.pair_count());
  EXPECT_TRUE(b.state().rolling_moment.empty());
  EXPECT_LT(plain.memory_bytes(), b.memory_bytes());

  DemCell no_bonds = plain;
  EXPECT_THROW(no_bonds.create_bonds(0.05), std::logic_error);
  // A state carrying bond arrays for a material without bonds is inconsistent.
  CellState st = b.state();
  EXPECT_THROW((void)DemCell(st, small_material(), b.skin()), std::invalid_argument);
}

TEST(ShearStress, SimpleShearOfPreparedCellGivesPositiveShearStress) {
  // Isochoric simple shear, L_xy > 0 (v_x = γ̇ y): a frictional packing resists with σ_xy > 0 in the
  // tension-positive convention (like a fluid's η γ̇), and σ_xy < 0 for the opposite sense.
  const Material mat = small_material();
  const DemCell prepared = prepare_cell(mat, small_spec(125, 10));
  const double p0 = pressure_of(prepared.measures().stress);
  for (double sense : {1.0, -1.0}) {
    DemCell cell = prepared;
    Substepping q;
    const double rate = 2, duration = 1e-4;  // inertial number ~ 1e-3: quasi-static
    const Mat3 inc = simple_shear(sense * rate * duration);
    IncrementResult res;
    for (int k = 0; k < 150; ++k) res = cell.advance(inc, duration, q);  // γ = 0.03
    SCOPED_TRACE(sense);
    EXPECT_NEAR(cell.volume(), prepared.volume(), 1e-12 * prepared.volume());
    const Mat3 s = res.stress;
    const double p = pressure_of(s);
    EXPECT_GT(p, 0.5 * p0) << "the sheared packing stays in compression";
    EXPECT_GT(sense * s(0, 1), 0.05 * p) << "σ_xy must have the sign of L_xy";
    EXPECT_LT(sense * s(0, 1), p) << "shear stress ratio above 1 is unphysical for μ = 0.5";
    EXPECT_NEAR(s(0, 1), s(1, 0), 0.1 * std::abs(s(0, 1))) << "quasi-static stress is nearly symmetric";
  }
}

}  // namespace
}  // namespace grainbank::dem::test
