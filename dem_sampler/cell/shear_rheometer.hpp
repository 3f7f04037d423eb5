// A plane-shear rheometer (issue 18, the μ(I) of a cell): steady simple shear at a prescribed
// inertial number under a controlled normal stress, the configuration of the GDR MiDi (2004) and of
// the μ(I) rheology (Jop, Forterre & Pouliquen 2006).
//
// The cell is first consolidated to the isotropic stress −P (servoed, quasi-static), then sheared at L_xy = γ̇ with γ̇ = I √(P/ρ_s) / d (d the mean diameter, ρ_s the grain
// density) while L_yy servoes σ_yy to −P (tension-positive), so the packing dilates or compacts as
// it flows; every other component of L is zero (plane strain, z fixed, as the MPM drives cells).
// Over the steady part of the strain it reports the effective friction μ = σ_xy / (−σ_yy) (means of
// each), the solid fraction and the coordination. The statistical error of μ comes from the spread
// of block means (10 blocks of equal strain), which are nearly independent once a block spans
// more than the strain over which the packing forgets its contacts.
//
// A bonded cell first carries a peak shear stress, before its bonds break and it flows: the strength
// that holds a slope or a column up. The rheometer also reports that peak (of σ_xy averaged over a
// strain of 0.005, from the start of shear), so that peaks at several P give the cell's Mohr–Coulomb
// envelope τ = c + P tan φ.
#pragma once
#include "dem_sampler/cell/dem_cell.hpp"

namespace grainbank::dem {

struct RheometerSettings {
  double inertial_number = 0;  // I > 0
  double normal_stress = 0;    // P [Pa] > 0
  double strain = 3;           // total shear strain γ
  double steady_from = 1;      // γ after which the flow counts as steady, < strain
  double q_t = 0.1;            // DEM time step factor of seed Eq. 3
};

struct RheometerResult {
  double inertial_number = 0;  // the one imposed
  double shear_rate = 0;       // γ̇ [1/s]
  double friction = 0;         // μ = ⟨σ_xy⟩ / ⟨−σ_yy⟩ over the steady part
  double friction_error = 0;   // standard error of μ from the block means
  double normal_stress = 0;    // ⟨−σ_yy⟩ [Pa]: the servo's hold on P
  double solid_fraction = 0;   // mean over the steady part
  double coordination = 0;     // mean over the steady part
  double peak_shear = 0;       // the largest σ_xy [Pa] (averaged over a strain of 0.005) of the whole shear
  double peak_strain = 0;      // γ at that peak
  long consolidation_steps = 0;  // steps of the isotropic consolidation to −P before the shear
  double consolidated_solid_fraction = 0;  // φ at its end
  long steps = 0;              // of the shear
};

// Consolidates and shears `cell` as above (the cell ends in its last state). Throws
// std::invalid_argument on bad settings and std::runtime_error if the consolidation fails or the
// stress becomes non-finite.
RheometerResult shear_at_inertial_number(DemCell& cell, const RheometerSettings& settings);

}  // namespace grainbank::dem
