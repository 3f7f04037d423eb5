// Drucker–Prager plasticity with cohesion and a tension cut-off, plane strain, with a dilatancy angle
// ψ (default 0: no dilatancy).
// Yield: sqrt(J2) ≤ η p + ξ c, p = -tr σ / 3. Plastic potential sqrt(J2) − η̄ p: the plastic strain
// rate is λ̇ (s / (2 sqrt(J2)) + η̄ I / 3), so the material dilates at tr ε̇ᵖ = η̄ λ̇.
// The constants match Mohr–Coulomb (φ, c, ψ) in steady plane-strain flow. There ε̇ᵖ_zz = 0 gives
// s_zz = −(2/3) η̄ sqrt(J2), hence sqrt(J2) = t / sqrt(1 − η̄²/3) with t = (σ1 − σ3)/2, and the in-plane
// dilatancy sin ψ = −(ε̇1 + ε̇3)/(ε̇1 − ε̇3) = η̄ / sqrt(1 − η̄²/3). Matching t = sin φ s + c cos φ
// (s = −(σ1 + σ3)/2) and that dilatancy:
//   η̄ = sin ψ / sqrt(1 + sin²ψ / 3),
//   η = sin φ / (sqrt(1 − η̄²/3) + η̄ sin φ / 3),   ξ = cos φ (1 − η η̄ / 3) / sqrt(1 − η̄²/3).
// With ψ = 0 this is η = sin φ, ξ = cos φ, purely deviatoric flow along s (steady plane-strain flow
// then has s_zz = 0, sqrt(J2) = (σ1 − σ3)/2 and p = (σ1 + σ3)/2). With ψ = φ the flow is associated
// and η = 3 tan φ / sqrt(9 + 12 tan²φ), the classic plane-strain match; the limit theorems of
// plasticity (Chen 1975) hold only for that associated material. One that dilates less collapses at
// lower loads, no lower than the associated material of c* = c cos φ, tan φ* = sin φ (Radenkovic);
// along a translational mechanism it behaves as the associated material of tan φ* = k tan φ,
// c* = k c, k = cos ψ cos φ / (1 − sin ψ sin φ) (Davis 1968; Drescher & Detournay 1993).
// Tension cut-off: the mean stress never exceeds the tensile strength T (p ≥ -T).
// Return mapping on the elastic trial stress: p is capped at -T, then the deviator is scaled back
// onto the cone along the potential's gradient: sqrt(J2) = sqrt(J2)* − G Δλ and p = p* + K η̄ Δλ, with
// Δλ = f* / (G + K η η̄) (radial at constant p when ψ = 0).
// Optionally rate-dependent (ψ = 0 only): with an InertialRheology the cone's friction is μ(I) from η
// = sin φ = μ_s on, at the inertial number of the plastic shear rate (inertial_rheology.hpp).
// Optionally separating (cohesionless only): a point pulled apart to the stress-free apex is a gas of
// grains out of contact, the "disconnected" state of Dunatunga & Kamrin (2015, J. Fluid Mech.
// 779:483). It carries no stress, and no stiffness, until it is packed back to the volume J_s at
// which it came apart; without it, a point dilated to J > J_s pushes back at once when compressed,
// with its full modulus on its dilated volume (a stiff gas, whose wave speed sqrt(M J / ρ0) also sets
// the step).
#pragma once
#include <optional>
#include <vector>

#include "mpm_solver/laws/elastic_law.hpp"
#include "mpm_solver/laws/inertial_rheology.hpp"

namespace grainbank::mpm {

struct DruckerPragerParameters {
  Elasticity elasticity;
  double friction_angle = 0;    // φ [rad], in [0, π/2)
  double cohesion = 0;          // c [Pa] ≥ 0
  double tensile_strength = 0;  // T [Pa], in [0, ξ c / η] (the apex of the cone)
  std::optional<InertialRheology> rheology;  // none: rate-independent
  double dilatancy_angle = 0;   // ψ [rad], in [0, φ]
  bool separation = false;      // pulled apart, carries nothing until packed back (cohesion 0 only)
};

class DruckerPragerLaw : public ConstitutiveLaw {
 public:
  DruckerPragerLaw(double density, DruckerPragerParameters parameters);

  std::string name() const override { return "drucker_prager"; }
  double density() const override { return density_; }
  std::size_t add_point(PointStress& initial_stress) override;
  void update(std::size_t slot, const KinematicIncrement& increment, const Mat2& F, PointStress& stress) override;
  // Of a separated point: the modulus it will have when packed back, counted at its current density
  // (the solver divides by it), so that its signal is the packed material's.
  double p_wave_modulus(std::size_t slot) const override;
  bool replicable() const override { return true; }
  void save_state(LawStateWriter& out) const override;
  void restore_state(LawStateReader& in) override;

  // The plastic correction alone (for tests): the admissible stress closest to `trial` in the sense
  // above, for a step of dt (which only the rate-dependent cone uses).
  PointStress return_map(const PointStress& trial, double dt) const;

 private:
  double density_;
  DruckerPragerParameters parameters_;
  double eta_, xi_, eta_bar_;
  // Per point, with `separation`: the volume ratio J_s at which it came apart (0: in contact), and
  // its volume ratio J after its last update.
  struct Packing {
    double separated_at = 0;
    double volume_ratio = 1;
  };
  std::vector<Packing> packing_;
};

}  // namespace grainbank::mpm
