// The wave speed of DEM-backed points (the CFL criterion): the cell's moduli estimated from its
// solid fraction and coordination against the exact affine response of a simple cubic lattice,
// K = k_n / (6R), and against the unrelaxed response of a prepared cell to one small step.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "dem_sampler/cell/dem_cell.hpp"
#include "dem_sampler/cell/preparation.hpp"
#include "dem_sampler/cell/snow_preset.hpp"
#include "mpm_solver/dem_laws/live_cell_model.hpp"
#include "tests/dem/dem_test_util.hpp"

namespace grainbank::mpm {
namespace {

// The stress change of one velocity-Verlet step at a uniform strain rate against the same step
// without strain: the grains have no time to relax, so this is the affine (unrelaxed) response.
// A second step at rest follows both, so that the contact dashpots, which resist the strain rate
// of the first step, no longer act when the stress is read. Returns Δσ per unit strain along
// `direction`.
dem::Mat3 unrelaxed_response(const dem::DemCell& cell, const dem::Mat3& direction) {
  const double strain = 1e-8, dt = cell.time_step(0.1);
  dem::DemCell strained = cell, still = cell;
  strained.step_with_velocity_gradient(direction * (strain / dt), dt);
  for (dem::DemCell* c : {&strained, &still}) c->step_with_velocity_gradient(dem::Mat3::Zero(), dt);
  still.step_with_velocity_gradient(dem::Mat3::Zero(), dt);
  return (strained.measures().stress - still.measures().stress) / strain;
}

TEST(CellWaveSpeed, SimpleCubicLatticeHasTheExactAffineBulkModulus) {
  const dem::Material material = dem::test::small_material();  // no bonds: contacts carry the full k_n
  const double R = 5e-4, spacing = 2 * R * (1 - 1e-4);  // touching, with a small overlap
  const int n = 4;
  std::vector<dem::Vec3> positions;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) positions.push_back(spacing * dem::Vec3(i + 0.5, j + 0.5, k + 0.5));
  const dem::DemCell lattice = dem::DemCell::from_packing(n * spacing * dem::Mat3::Identity(), positions,
                                                          std::vector<double>(positions.size(), R), material, 0.2 * R);
  const dem::CellMeasures m = lattice.measures();
  ASSERT_NEAR(m.coordination, 6, 1e-12);
  ASSERT_NEAR(m.solid_fraction, std::numbers::pi / 6, 1e-3);

  // Isotropic compression: Δp = K Δε_vol.
  const dem::Mat3 response = unrelaxed_response(lattice, -dem::Mat3::Identity());
  const double measured_bulk = -response.trace() / 3 / 3;
  const double exact = material.contact.k_n / (6 * R);
  EXPECT_NEAR(measured_bulk, exact, 1e-3 * exact) << "the lattice itself";
  const dem::ElasticModuli estimate =
      dem::voigt_moduli(m.solid_fraction, m.coordination, R, material.contact.k_n, material.contact.k_t);
  EXPECT_NEAR(estimate.bulk, exact, 1e-3 * exact);
}

// A prepared, bonded snow cell: the unrelaxed uniaxial-strain modulus M = Δσ_xx/Δε_xx is the
// P-wave modulus of the CFL criterion. Its pairs carry w_c k_n (contact), w_b k_n (bond) or both, so
// the affine response lies between half the Voigt estimate (made with the full k_n) and the
// estimate itself, up to the spread of the radii (ℓ² against (2R̄)²).
TEST(CellWaveSpeed, PreparedCellUnrelaxedModulusIsBoundedByTheEstimate) {
  const dem::DemCell cell = dem::prepare_cell(dem::snow_material(), dem::snow_preparation(125, 3));
  const LiveCellModel model(cell, LiveDemSettings{});
  dem::Mat3 uniaxial = dem::Mat3::Zero();
  uniaxial(0, 0) = -1;
  const double measured = -unrelaxed_response(cell, uniaxial)(0, 0);
  const double estimate = model.modulus(cell.measures());
  std::printf("unrelaxed M = %.4g Pa, Voigt estimate %.4g Pa (ratio %.3f)\n", measured, estimate, measured / estimate);
  EXPECT_LE(measured, 1.1 * estimate);
  EXPECT_GE(measured, 0.5 / 1.1 * estimate);
}

}  // namespace
}  // namespace grainbank::mpm
