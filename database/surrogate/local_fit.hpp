// The local model of the surrogate: a weighted linear fit of the answers of a query's k nearest
// samples, and an estimate of its error from the same neighbourhood.
//
// With z_i the scaled offset of neighbour i from the query (feature differences divided by the
// length scales), d_i = |z_i| sorted, h = 1.5 d_k and tricube weights w_i = (1 − (d_i/h)³)³:
//   minimize Σ w_i |y_i − a − B z_i|² + λ Σw |B|²    (ridge on the slopes only; λ = ridge)
// for each answer component; the prediction is the intercept a (the fit is centred on the query).
//
// Error estimate (per answer component, and the Frobenius norm of the stress part):
//   e_i = (y_i − a − B z_i) / (1 − H_ii)   the exact leave-one-out residual of neighbour i
//                                          (PRESS; H the weighted ridge hat matrix)
//   press² = Σ w_i e_i² / Σ w_i           how wrong this local model is on points like its own
//   spread² = Σ w_i |y_i − ȳ|² / Σ w_i    how much the answer varies in the neighbourhood
//   error² = press² + (d_1 · spread)²     the second term grows as the query leaves the samples
//                                          (d_1 = distance to the nearest, in length scales)
// With fewer than two neighbours the error is +∞: one sample tells nothing of its own error.
#pragma once
#include <cstddef>
#include <vector>

#include "database/surrogate/rate_answer.hpp"
#include "database/surrogate/state_features.hpp"

namespace grainbank::surrogate {

struct Neighbour {
  FeatureVector offset{};  // z_i, scaled
  double distance = 0;     // |z_i|
  const Answer* answer = nullptr;
};

struct LocalFit {
  Answer answer{};        // predicted normalized answer
  Answer error{};         // estimated error of each component (same units)
  double stress_error = 0;  // estimated error of the stress part, Frobenius norm (stress_norm units)
};

// `neighbours` sorted by distance; ridge λ ≥ 0.
LocalFit local_fit(const std::vector<Neighbour>& neighbours, double ridge);

}  // namespace grainbank::surrogate
