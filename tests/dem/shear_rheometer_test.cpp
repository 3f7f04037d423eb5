// The plane-shear rheometer: it holds the normal stress it is given, the packing dilates and its
// friction rises as the flow gets faster (the μ(I) and φ(I) of dense granular flows, GDR MiDi 2004),
// and slow flow of spheres with μ_p = 0.5 has the published quasi-static friction μ_s ≈ 0.35–0.40.
// A bonded cell is consolidated to P before it is sheared, and carries a peak shear stress, reached
// at a small strain, above what it carries once its bonds near the shear have broken.
#include <gtest/gtest.h>

#include <cstdio>

#include "dem_sampler/cell/preparation.hpp"
#include "dem_sampler/cell/shear_rheometer.hpp"
#include "dem_sampler/cell/snow_preset.hpp"

namespace grainbank::dem {
namespace {

// Frictional spheres (μ_p = 0.5) without bonds, contacts carrying the full k_n, dense.
const DemCell& frictional_cell() {
  static const DemCell cell = [] {
    Material m = snow_material();
    m.effects.bonds = false;
    m.contact.friction = 0.5;
    m.contact.contact_weight = 1;
    return prepare_cell(m, snow_preparation(64, 7));
  }();
  return cell;
}

RheometerResult shear(double inertial_number) {
  DemCell cell = frictional_cell();
  RheometerSettings s;
  s.inertial_number = inertial_number;
  s.normal_stress = 1000;
  s.strain = 4;
  s.steady_from = 1;
  const RheometerResult r = shear_at_inertial_number(cell, s);
  std::printf("I = %g: mu = %.3f ± %.3f, P = %.1f Pa, phi = %.4f, Z = %.2f\n", inertial_number, r.friction,
              r.friction_error, r.normal_stress, r.solid_fraction, r.coordination);
  return r;
}

TEST(ShearRheometer, FasterFlowIsLooserAndMoreFrictionalUnderTheSameNormalStress) {
  const RheometerResult slow = shear(0.01), fast = shear(0.2);
  for (const RheometerResult* r : {&slow, &fast}) EXPECT_NEAR(r->normal_stress, 1000, 20);
  EXPECT_GT(fast.friction, slow.friction + fast.friction_error + slow.friction_error);
  EXPECT_LT(fast.solid_fraction, slow.solid_fraction);
  // Quasi-static friction of μ_p = 0.5 spheres (issue 18's published range), plus Jop et al.'s rise
  // of about 0.01 at I = 0.01 and three standard errors.
  EXPECT_GT(slow.friction, 0.35 - 3 * slow.friction_error);
  EXPECT_LT(slow.friction, 0.41 + 3 * slow.friction_error);
}

TEST(ShearRheometer, ABondedCellIsConsolidatedThenPeaksBeforeItsBondsBreak) {
  DemCell cell = prepare_cell(snow_material(), snow_preparation(64, 7));
  const double prepared_pressure = -cell.stress().trace() / 3;
  RheometerSettings s;
  s.inertial_number = 1e-3;
  s.normal_stress = 3 * prepared_pressure;
  s.strain = 0.15;
  s.steady_from = 0.1;
  const RheometerResult r = shear_at_inertial_number(cell, s);
  std::printf("P = %.0f Pa: consolidated in %ld steps to phi = %.3f; peak %.0f Pa at strain %.3f; residual %.0f Pa\n",
              s.normal_stress, r.consolidation_steps, r.consolidated_solid_fraction, r.peak_shear, r.peak_strain,
              r.friction * r.normal_stress);
  EXPECT_GT(r.consolidation_steps, 0);  // three times the preparation pressure: compressed first
  EXPECT_NEAR(r.normal_stress, s.normal_stress, 0.1 * s.normal_stress);
  EXPECT_GT(r.peak_shear, r.friction * r.normal_stress);
  EXPECT_LT(r.peak_strain, 0.05);  // brittle bonds: the peak comes within a few percent of strain
}

TEST(ShearRheometer, BadSettingsAreRefused) {
  DemCell cell = frictional_cell();
  RheometerSettings s;
  s.normal_stress = 1000;
  EXPECT_THROW(shear_at_inertial_number(cell, s), std::invalid_argument);  // no inertial number
  s.inertial_number = 0.01;
  s.steady_from = s.strain;
  EXPECT_THROW(shear_at_inertial_number(cell, s), std::invalid_argument);
  s = RheometerSettings{};
  s.normal_stress = 1000;
  s.inertial_number = 0.01;
  s.q_t = 1.01 * max_time_step_factor(cell.material().contact.restitution);  // beyond what its dashpots allow
  try {
    shear_at_inertial_number(cell, s);
    FAIL() << "Q_t " << s.q_t << " accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("rheometer: q_t: expected a number in (0, "), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace grainbank::dem
