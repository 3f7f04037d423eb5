// Material of a periodic DEM cell: the parameters of the interaction law of seed Fig. 1 and the set
// of optional effects. Pure data plus a consistency check; no I/O.
#pragma once
#include <string>

namespace grainbank::dem {

// Frictional visco-elastic contact between spheres (seed Fig. 1 a, b).
struct ContactLaw {
  double k_n = 0;           // normal stiffness [N/m] (full stiffness; contact carries w_c of it)
  double k_t = 0;           // tangential stiffness [N/m]
  double restitution = 0.5; // normal coefficient of restitution e_n in (0, 1]; sets the damping ratio
  double friction = 0.5;    // Coulomb coefficient μ >= 0
  double contact_weight = 0.5;  // w_c in [0, 1]; the bond carries w_b = 1 - w_c
};

// Elastic-brittle bond (seed Fig. 1, "omitting bond damage"), or softening past its yield surface.
struct BondLaw {
  double tensile_strength = 0;   // T_0 [N]
  double shear_strength = 0;     // S_0 [N]
  double exponent = 2;           // p in Φ = T/T_0 + (S/S_0)^p - 1
  double bonding_distance = 0;   // pairs with gap < ε·(R_i + R_j) are bonded at preparation
  // ρ >= 0: past its yield surface a bond's force falls linearly to zero over ρ times its elastic
  // displacement at yield (interaction_law.hpp, softening_integrity), so it dissipates (1 + ρ) times
  // the elastic energy a brittle bond releases. 0: elastic-brittle, the seed's bond. Not in the seed:
  // a less brittle bond, to study what the cell's brittleness does (README, "The two-scale cohesive
  // column").
  double softening = 0;
};

// Rolling resistance (optional effect): elastic rolling spring capped by μ_r R_eff f_n.
struct RollingLaw {
  double stiffness = 0;   // k_r [N·m/rad]
  double friction = 0;    // μ_r (dimensionless)
};

// Effects that cost something only when switched on (no arrays, no branches otherwise).
struct Effects {
  bool bonds = false;           // cohesion: elastic-brittle bonds
  bool kinetic_stress = false;  // Σ m v'⊗v' term of seed Eq. 2
  bool rolling = false;         // rolling resistance
  bool operator==(const Effects&) const = default;
};

struct Material {
  double density = 0;  // grain density [kg/m^3]
  ContactLaw contact;
  BondLaw bond;
  RollingLaw rolling;
  Effects effects;
};

// Throws std::invalid_argument naming the first offending parameter, the expected range and the
// value found, e.g. "contact.k_n: expected a positive number, got -5".
void check(const Material& material);

// Damping ratio ζ of a linear spring-dashpot whose restitution coefficient is e:
// ζ = -ln e / sqrt(π² + ln² e)   (e = 1 gives ζ = 0).
double damping_ratio_from_restitution(double e);

}  // namespace grainbank::dem
