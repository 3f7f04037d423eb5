// The mirror symmetry of the surrogate's material. A random packing has no handedness: reflected
// about a principal axis of σ (x → −x in the answer frame of rate_answer.hpp), a state keeps σ, φ, Z
// and D, its loading D = sym L keeps D_xx, D_yy, D_zz and turns D_xy into −D_xy, so β → −β, and the
// answer keeps every component but Â_xy, which changes sign. The rotations about z are already
// factored out by the frame-free key; this is the other half of the plane's symmetry group O(2).
//
// Why it matters: a library covers β sparsely, and a local fit of Â_xy against the β features then
// has no reason to vanish on the mirror plane β = 0 (or ±π/2), where symmetry says it must. A point
// compressed along a principal axis of its stress from an isotropic state would gain shear stress
// it can never have (measured on the demo's library: σ_xy 3.9 kPa against live's 0.2 kPa after 1 %
// oedometric strain). SurrogateIndex averages each prediction with the mirrored prediction of the
// mirrored state, which is exactly symmetric, and counts their disagreement as error.
#pragma once
#include "database/surrogate/rate_answer.hpp"
#include "database/surrogate/state_features.hpp"

namespace grainbank::surrogate {

// cos ψ sin 2β, the one feature the reflection changes (feature_vector in state_features.hpp).
inline constexpr std::size_t kMirrorOddFeature = 8;
// Â_xy, the one answer component the reflection changes (rate_answer.hpp).
inline constexpr std::size_t kMirrorOddAnswer = 3;

inline FeatureVector mirrored(FeatureVector features) {
  features[kMirrorOddFeature] = -features[kMirrorOddFeature];
  return features;
}

inline Answer mirrored(Answer answer) {
  answer[kMirrorOddAnswer] = -answer[kMirrorOddAnswer];
  return answer;
}

}  // namespace grainbank::surrogate
