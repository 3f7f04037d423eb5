// The interaction law between two spheres i and j: frictional visco-elastic contact in parallel
// with an elastic-brittle bond, as in seed Fig. 1 ("omitting bond damage"), or a softening one. All of
// the force law lives here; dem_cell_forces.cpp only gathers geometry and scatters the results.
//
// Conventions: n is the unit vector from i to j, gap d_n = |ℓ| - R_i - R_j (< 0: overlap), forces
// are those exerted on j (i receives the opposite), a positive normal force pushes j away from i.
// The contact point sits mid-gap, at R_i + d_n/2 from i and R_j + d_n/2 from j (these lever arms add
// up to |ℓ|, so a rigidly rotating pair does not slip). "slip" is the tangential relative
// displacement of the contact point during the step, v_t δt; "twist" the pair's mean spin about n
// times δt.
#pragma once
#include <algorithm>
#include <cmath>

#include "dem_sampler/cell/cell_state.hpp"
#include "dem_sampler/cell/lane_vector.hpp"
#include "dem_sampler/cell/material.hpp"

namespace grainbank::dem {

// Stiffness split and strengths, derived once from a Material.
struct InteractionCoefficients {
  double kn_contact = 0, kt_contact = 0;  // w_c k_n, w_c k_t
  double friction = 0;                    // μ
  double kn_bond = 0, kt_bond = 0;        // w_b k_n, w_b k_t with w_b = 1 - w_c
  double inv_tensile_strength = 0, inv_shear_strength = 0, exponent = 2;
  double inv_softening = 0;               // 1/ρ (0 when brittle: never read)
  double rolling_stiffness = 0, rolling_friction = 0;
  double damping_ratio = 0;               // ζ from the restitution coefficient

  explicit InteractionCoefficients(const Material& m)
      : kn_contact(m.contact.contact_weight * m.contact.k_n),
        kt_contact(m.contact.contact_weight * m.contact.k_t),
        friction(m.contact.friction),
        kn_bond((1 - m.contact.contact_weight) * m.contact.k_n),
        kt_bond((1 - m.contact.contact_weight) * m.contact.k_t),
        inv_tensile_strength(m.effects.bonds ? 1 / m.bond.tensile_strength : 0),
        inv_shear_strength(m.effects.bonds ? 1 / m.bond.shear_strength : 0),
        exponent(m.bond.exponent),
        inv_softening(m.bond.softening > 0 ? 1 / m.bond.softening : 0),
        rolling_stiffness(m.rolling.stiffness),
        rolling_friction(m.rolling.friction),
        damping_ratio(damping_ratio_from_restitution(m.contact.restitution)) {}

  // Normal dashpot c_n = 2 ζ sqrt(m_ij w_c k_n), m_ij = m_i m_j / (m_i + m_j): a contact of this pair
  // alone rebounds with the material's restitution coefficient e_n.
  double pair_damping(double m_i, double m_j) const {
    return 2 * damping_ratio * std::sqrt(m_i * m_j / (m_i + m_j) * kn_contact);
  }
};

// Every function below is a pure function of its arguments, free of branches on the data (a choice
// between two computed values is a select): the force loop evaluates them for several pairs at once
// (a SIMD register's worth) and masks out what does not apply to a pair.

// Objectivity of tangential history (a tangential spring force or bond shear displacement): turn t
// with the contact frame, i.e. bring it back into the plane normal to the new n and twist it about n
// by the pair's mean spin, (ω_i + ω_j)·n δt / 2. A rigid rotation of the pair then carries t along
// instead of loading it. Its length changes only at second order in the per-step turn θ and twist φ,
// by (φ² - θ²)/2 relative (about 1e-10 per step in practice); not rescaling it saves a division
// per contact, as in LAMMPS.
inline LaneVec rotated_with_contact_frame(const LaneVec& t, const LaneVec& n, double twist) {
  return t + twist * cross(n, t) - dot(t, n) * n;
}

// The factor that brings a spring force (or moment) of squared length `length2` within `cap`:
// min(1, cap / sqrt(length2)).
inline double coulomb_factor(double length2, double cap) {
  return length2 > cap * cap ? cap / std::sqrt(length2) : 1.0;
}

// Contact, normal part (seed Fig. 1a): f_c = -w_c k_n d_n - c_n v_n, for d_n < 0.
// The dashpot is not clipped, so an isolated collision has exactly the restitution coefficient e_n.
inline double contact_normal_force(const InteractionCoefficients& c, double gap, double normal_velocity,
                                   double damping) {
  return -c.kn_contact * gap - damping * normal_velocity;
}

// Contact, tangential part (seed Fig. 1b): incremental spring f_t <- R(f_t) - w_c k_t v_t δt,
// capped by Coulomb |f_t| <= μ f_n. Returns the new f_t.
inline LaneVec friction_force(const InteractionCoefficients& c, const LaneVec& n, double twist, const LaneVec& slip,
                           double normal_force, const LaneVec& previous) {
  const LaneVec trial = rotated_with_contact_frame(previous, n, twist) - c.kt_contact * slip;
  return trial * coulomb_factor(squared_norm(trial), c.friction * std::max(normal_force, 0.0));
}

// Bond yield function Φ = T/T_0 + (S/S_0)^p - 1 (seed Fig. 1 bottom), T the tension (> 0 pulled),
// S the magnitude of the bond shear force, given as S². The usual p = 2 (Quadratic) needs neither a
// square root nor a power, and so vectorizes.
template <bool Quadratic>
inline double bond_yield(const InteractionCoefficients& c, double tension, double shear_squared) {
  const double s2 = shear_squared * c.inv_shear_strength * c.inv_shear_strength;
  const double sp = Quadratic ? s2 : std::pow(s2, 0.5 * c.exponent);
  return tension * c.inv_tensile_strength + sp - 1;
}

// Bond (seed Fig. 1a,b, red): normal -w_b k_n (d_n - g_0) in tension and compression ("canceling
// u_n^0"), shear -w_b k_t u_b with u_b the total tangential displacement since bonding.
// Elastic-brittle: when the trial forces reach Φ >= 0 the bond breaks and carries nothing from this
// step on; the contact law alone then acts on the pair (seed Fig. 1 bottom, force jumps).
struct BondStep {
  LaneVec shear_displacement;  // u_b after the step
  double tension;           // T = w_b k_n (d_n - g_0): the bond's normal force on j is -T
  double shear_squared;     // S² = (w_b k_t |u_b|)²
  bool holds;               // Φ < 0: intact after the step
};
template <bool Quadratic>
inline BondStep bond_step(const InteractionCoefficients& c, const LaneVec& shear_displacement, double rest_gap,
                          double gap, const LaneVec& n, double twist, const LaneVec& slip) {
  BondStep b;
  b.shear_displacement = rotated_with_contact_frame(shear_displacement, n, twist) + slip;
  b.tension = c.kn_bond * (gap - rest_gap);
  b.shear_squared = c.kt_bond * c.kt_bond * squared_norm(b.shear_displacement);
  b.holds = bond_yield<Quadratic>(c, b.tension, b.shear_squared) < 0;
  return b;
}

// Softening bond (BondLaw::softening ρ > 0; not in the seed, whose bonds are brittle). The load
// factor λ scales the elastic trial forces onto the yield surface, Φ(T/λ, S/λ) = 0; for p = 2 that is λ² - t λ - s² = 0 with
// t = T/T_0, s = S/S_0, so λ = (t + √(t² + 4 s²))/2 (λ >= 1 exactly where Φ >= 0). Past λ = 1 the
// force falls linearly to zero at λ = 1 + ρ: the bond carries its trial forces times the secant
// integrity w(λ) = (1 - (λ - 1)/ρ)/λ, clamped to [0, 1]. The caller keeps the least w the bond has
// had, so a softened bond unloads and reloads along its secant, as a damaged spring, and never heals.
// Along a fixed loading direction it dissipates ½ F_y δ_y (1 + ρ), F_y and δ_y its force and
// displacement at yield.
inline double softening_integrity(const InteractionCoefficients& c, double tension, double shear_squared) {
  const double t = tension * c.inv_tensile_strength;
  const double s2 = shear_squared * c.inv_shear_strength * c.inv_shear_strength;
  const double load = std::max(0.5 * (t + std::sqrt(t * t + 4 * s2)), 1.0);
  return std::max((1 - (load - 1) * c.inv_softening) / load, 0.0);
}

// Rolling resistance (optional): a rolling spring M <- R(M) - k_r Δθ_r, Δθ_r = ((ω_j - ω_i) δt)⊥n the
// relative rolling rotation of the step, capped by μ_r R_ij f_n with R_ij = R_i R_j / (R_i + R_j).
// M stays ⟂ n and turns with the contact frame like the tangential spring, so a rigidly rotating pair
// carries its moment along and loads no new one. Twisting about n is not resisted: the model has no
// twisting law (RollingLaw holds k_r and μ_r only), and a twist must not eat into the rolling cap.
// The moment acts on j; i receives -M. Returns the new M.
inline LaneVec rolling_moment(const InteractionCoefficients& c, const LaneVec& n, double twist,
                           const LaneVec& relative_rotation, double radius_ij, double normal_force,
                           const LaneVec& previous) {
  const LaneVec trial = rotated_with_contact_frame(previous, n, twist) -
                     c.rolling_stiffness * (relative_rotation - dot(relative_rotation, n) * n);
  return trial * coulomb_factor(squared_norm(trial), c.rolling_friction * radius_ij * std::max(normal_force, 0.0));
}

}  // namespace grainbank::dem
