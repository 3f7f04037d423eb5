// Drucker–Prager plasticity with cohesion and a tension cut-off, plane strain, no dilatancy.
// Yield: sqrt(J2) ≤ η p + ξ c, p = -tr σ / 3, with η = sin φ, ξ = cos φ: the match to Mohr–Coulomb
// for this return. Plastic flow is deviatoric and along s, so steady plane-strain flow (ε̇_zz = 0)
// has s_zz = 0; then sqrt(J2) = (σ1 − σ3)/2 and p = (σ1 + σ3)/2, and the cone is Mohr–Coulomb's
// (σ1 − σ3)/2 = sin φ (σ1 + σ3)/2 + c cos φ. (The match η = 3 tan φ / sqrt(9 + 12 tan² φ) belongs to
// an associated, dilatant flow rule; with this return it flows at (σ1 − σ3)/(σ1 + σ3) = 0.48 instead
// of sin 30° = 0.5.)
// Tension cut-off: the mean stress never exceeds the tensile strength T (p ≥ -T).
// Return mapping on the elastic trial stress: p is capped at -T, then the deviator is scaled back
// radially onto the cone (zero dilatancy: plastic flow is purely deviatoric).
// Optionally rate-dependent: with an InertialRheology the cone's friction is μ(I) from η = sin φ
// = μ_s on, at the inertial number of the plastic shear rate (inertial_rheology.hpp).
#pragma once
#include <optional>

#include "mpm_solver/laws/elastic_law.hpp"
#include "mpm_solver/laws/inertial_rheology.hpp"

namespace grainbank::mpm {

struct DruckerPragerParameters {
  Elasticity elasticity;
  double friction_angle = 0;    // φ [rad], in [0, π/2)
  double cohesion = 0;          // c [Pa] ≥ 0
  double tensile_strength = 0;  // T [Pa], in [0, ξ c / η] (the apex of the cone)
  std::optional<InertialRheology> rheology;  // none: rate-independent
};

class DruckerPragerLaw : public ConstitutiveLaw {
 public:
  DruckerPragerLaw(double density, DruckerPragerParameters parameters);

  std::string name() const override { return "drucker_prager"; }
  double density() const override { return density_; }
  std::size_t add_point(PointStress& initial_stress) override;
  void update(std::size_t slot, const KinematicIncrement& increment, const Mat2& F, PointStress& stress) override;
  double p_wave_modulus(std::size_t) const override { return parameters_.elasticity.p_wave_modulus(); }
  bool replicable() const override { return true; }

  // The plastic correction alone (for tests): the admissible stress closest to `trial` in the sense
  // above, for a step of dt (which only the rate-dependent cone uses).
  PointStress return_map(const PointStress& trial, double dt) const;

 private:
  double density_;
  DruckerPragerParameters parameters_;
  double eta_, xi_;
  std::size_t points_ = 0;
};

}  // namespace grainbank::mpm
