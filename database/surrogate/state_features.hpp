// The frame-free key of the state-keyed surrogate (issue 13, DESIGN.md "State key"): a point's
// state (σ, φ, Z, D) and its loading D = sym L, seen relative to each other.
//
//   ln(p/p_ref)      for p = −tr σ/3 ≥ p_floor; below it (loose or tensile cells), where the
//                    normalizing pressure stays p_floor (point_state.hpp), the mirrored logarithm
//                    ln(p_floor/p_ref) − ln(2 − p/p_floor): monotone, C¹, tension kept apart
//   η = q/p          q = √(3/2 s:s), s = dev σ, p = max(−tr σ/3, p_floor)
//   Lode angle θ     cos 3θ = (3√3/2) J₃ / J₂^{3/2} of s, θ ∈ [0, π/3]: θ = 0 when one principal
//                    stress is less compressive than the two others alike (triaxial extension),
//                    θ = π/3 when one is more compressive (triaxial compression); θ := 0 when q = 0
//                    (the distance uses η cos 3θ, η sin 3θ, continuous there).
//   φ, Z, D          as carried by the point
//   ψ = atan(tr D / |dev D|) ∈ [−π/2, π/2]   dilatancy direction of the loading (3-D norms)
//   β = θ_D − θ_σ ∈ (−π/2, π/2]  angle from the in-plane principal axis of σ (its largest, least
//                    compressive eigenvalue) to that of D (its largest stretching), both in the
//                    x–y plane: the MPM is plane strain, L has no z row or column, so only rotations
//                    about z can occur and the principal axes of dev D and σ can only differ by a
//                    turn about z. β := 0 when D has no in-plane axes; when σ has none, β is
//                    measured from D's own axes (answer_frame_angle), so β = 0 too.
//   I = |D| d √(ρ/p) the inertial number (|D| Frobenius norm of D)
//
// Promise: every feature is unchanged by a superposed rigid rotation about z (σ → QσQᵀ, L → QLQᵀ),
// finite for every finite input (p ≤ 0 included, D = 0 included: ψ = β = 0, I = 0).
//
// Distances are measured on a continuous embedding of these features (feature_vector): the polar
// pairs (η, 3θ) and the loading direction are written as Cartesian coordinates so that states
// whose angles are undefined or wrap around (q = 0, |D| = 0, β = ±π/2) sit next to their neighbours.
#pragma once
#include <array>
#include <cstddef>
#include <optional>
#include <string_view>

#include "database/surrogate/point_state.hpp"

namespace grainbank::surrogate {

struct StateFeatures {
  double log_pressure = 0;  // ln(p/p_ref), mirrored below p_floor (pressure_feature)
  double eta = 0;           // q/p
  double lode = 0;          // θ [rad]
  double solid_fraction = 0, coordination = 0, damage = 0;
  double psi = 0;           // [rad]
  double beta = 0;          // [rad]
  double inertial = 0;      // I
};

StateFeatures state_features(const PointState& state, const dem::Mat3& L, const FeatureConstants& constants);

// The pressure feature of −tr σ/3 = `pressure`, and the normalizing pressure max(p, p_floor) of a
// feature value (the inverse above the floor).
double pressure_feature(double pressure, const FeatureConstants& constants);
double effective_pressure_of_feature(double feature, const FeatureConstants& constants);

// ln(p/p_ref), η cos 3θ, η sin 3θ, φ, Z, D, sin ψ, cos ψ cos 2β, cos ψ sin 2β, ln max(I, 1e-8).
inline constexpr std::size_t kFeatureCount = 10;
using FeatureVector = std::array<double, kFeatureCount>;
FeatureVector feature_vector(const StateFeatures& features);
// The entries of feature_vector, in its order, as reports name them.
inline constexpr std::array<std::string_view, kFeatureCount> kFeatureNames = {
    "ln_p", "eta_cos_3theta", "eta_sin_3theta", "phi", "Z", "D", "sin_psi", "cos_psi_cos_2beta", "cos_psi_sin_2beta",
    "ln_I"};

// In-plane principal angle of a symmetric tensor: the direction of its largest in-plane eigenvalue,
// ½ atan2(2 T_xy, T_xx − T_yy) ∈ (−π/2, π/2]; none when the in-plane deviator vanishes.
std::optional<double> in_plane_principal_angle(const dem::Mat3& tensor);

// The in-plane frame in which answers are expressed (rate_answer.hpp): the principal axes of σ, or
// when σ has none in the plane (in-plane isotropic), those of D = sym L, or else the lab axes. It turns
// with any superposed rotation about z, so answers in it are frame-free.
double answer_frame_angle(const dem::Mat3& stress, const dem::Mat3& L);

}  // namespace grainbank::surrogate
