// The answer of the state-keyed surrogate (issue 13): how the state of a point changes per unit of
// loading, made dimensionless and frame-free, and its inverse, which advances a point's state.
//
// Objective rate. The MPM turns a point's stress with the spin W = skew L as R = exp(W Δt),
// σ ← R σ Rᵀ + … (mpm_solver/core/elastic_law.cpp), i.e. σ̇ = σ̇ᴶ + W σ − σ W with the Jaumann rate
// σ̇ᴶ. Over a recorded interval k → k+1 of constant L (tension-positive σ, as stored):
//   σ̇ᴶ = (Rᵀ σ_{k+1} R − σ_k) / Δt  =  (σ_{k+1} − σ_k)/Δt − W σ_k + σ_k W + O(Δt),
// the rotation-exact form of the usual first-order difference, and its inverse
//   σ_{k+1} = R (σ_k + σ̇ᴶ Δt) Rᵀ
// is exact, so a stored interval is reproduced by its own answer to round-off (but for the
// out-of-plane shears, see below), and a rigid spin alone turns σ without changing its invariants,
// however long the step.
//
// Normalization. With p = max(−tr σ_k/3, p_floor) (point_state.hpp), |D| = ‖sym L‖ and Q the turn
// about z by answer_frame_angle(σ_k, L) (the in-plane principal axes of σ_k, state_features.hpp):
//   answer = ( Â_xx, Â_yy, Â_zz, Â_xy,  Ż/|D|, Ḋ/|D| ),   Â = Qᵀ σ̇ᴶ Q / (p |D|).
// The solid fraction is not answered but follows the kinematics, as in the cell: its spheres keep
// their volume while the cell's follows det F, so over the interval φ_{k+1} = φ_k exp(−tr L Δt)
// exactly (mass conservation). Learned, it drifted from the point's own volume change, and φ is
// part of the key (issue 13 asked for φ̇ in the answer; the kinematics give it without error).
// The out-of-plane shears Â_xz, Â_yz are not part of the answer: under plane strain they are only
// the noise of the contact sum; a point keeps its σ_xz, σ_yz and turns them with R.
#pragma once
#include <array>
#include <cstddef>

#include "database/surrogate/point_state.hpp"

namespace grainbank::surrogate {

inline constexpr std::size_t kAnswerSize = 6;
inline constexpr std::size_t kStressAnswers = 4;  // Â_xx, Â_yy, Â_zz, Â_xy come first
using Answer = std::array<double, kAnswerSize>;

// Throws std::invalid_argument unless Δt > 0 and |D| > 0 (a rest or a pure spin has no rate per |D|).
Answer rate_answer(const PointState& before, const PointState& after, const dem::Mat3& L, double dt,
                   const FeatureConstants& constants);

// The state after Δt under L, given the answer for (state, L). |D| = 0: σ only turns by R.
// φ follows tr L (above) within (0, 1), Z ≥ 0, and D in [D_k, 1] (damage does not heal: broken
// bonds are not remade).
PointState advance(const PointState& state, const dem::Mat3& L, double dt, const Answer& answer,
                   const FeatureConstants& constants);

// p |D|: the stress rate [Pa/s] of a unit normalized answer at (σ, L). An error ε of the stress part
// of an answer (Frobenius norm) is an error ε p |D| Δt [Pa] on the stress after Δt.
double answer_scale(const dem::Mat3& stress, const dem::Mat3& L, const FeatureConstants& constants);

// Frobenius norm of the stress part of an answer, (Â_xx² + Â_yy² + Â_zz² + 2 Â_xy²)^½.
double stress_norm(const Answer& answer);

}  // namespace grainbank::surrogate
