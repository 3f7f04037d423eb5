// Effective-medium (Voigt, affine) moduli of a packing of spheres of mean radius R at solid fraction
// φ and coordination Z whose pairs have normal and tangential stiffnesses k_n, k_t: every pair
// follows the mean strain, so K = φ Z k_n / (6 π R) and G = φ Z (2 k_n + 3 k_t) / (20 π R) (on a
// simple cubic lattice, K = k_n / (6R) exactly). Relaxation of the grains only softens a packing,
// so these bound its true moduli from above: a wave speed from them bounds the true one, and a
// servo whose gain uses them does not overshoot.
#pragma once

namespace grainbank::dem {

struct ElasticModuli {
  double bulk = 0, shear = 0;
  double p_wave() const { return bulk + 4 * shear / 3; }
};

ElasticModuli voigt_moduli(double solid_fraction, double coordination, double mean_radius, double k_n, double k_t);

}  // namespace grainbank::dem
