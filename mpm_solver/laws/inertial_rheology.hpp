// The μ(I) rheology of dense granular flow (Jop, Forterre & Pouliquen 2006, Nature 441:727): the
// friction of a flowing granular material grows with its inertial number
//   I = γ̇ d / sqrt(p / ρ_s),   μ(I) = μ_s + (μ_2 − μ_s) / (I_0 / I + 1),
// from μ_s at quasi-static flow to μ_2 at I ≫ I_0 (d: grain diameter, ρ_s: grain density,
// γ̇ = sqrt(2) |D_dev|, the shear rate of simple shear). The same inertial number as the seed's
// (§2.2), at the continuum scale: the elasto-viscoplastic return of Dunatunga & Kamrin (2015, J.
// Fluid Mech. 779:483) with a Drucker–Prager cone at μ(I).
#pragma once

namespace grainbank::mpm {

struct InertialRheology {
  double mu_2 = 0;               // friction at large I, ≥ μ_s
  double inertial_number_0 = 0;  // I_0 > 0
  double grain_diameter = 0;     // d [m] > 0
  double grain_density = 0;      // ρ_s [kg/m³] > 0

  // μ(I) for a given quasi-static friction μ_s.
  double friction(double mu_s, double inertial_number) const;

  // The viscoplastic return at pressure p > 0: the shear rate γ̇ ≥ 0 at which the relaxed
  // equivalent shear stress τ = τ_trial − G Δt γ̇ equals the strength μ(I(γ̇)) p + k, with
  // excess = τ_trial − (μ_s p + k) > 0 the elastic trial's excess over the static strength.
  // Solves the quadratic that the equation becomes in γ̇ (it has exactly one positive root).
  double plastic_shear_rate(double excess, double mu_s, double p, double shear_modulus, double dt) const;
};

// Throws std::invalid_argument naming the offending parameter.
void check(const InertialRheology& r, double mu_s);

}  // namespace grainbank::mpm
