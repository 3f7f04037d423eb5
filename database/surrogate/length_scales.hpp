// Per-feature length scales of the surrogate, fitted by leave-one-out on its dataset (issue 13).
//
// Start: each feature's standard deviation over the dataset (1 where it does not vary). Loss: the
// mean stress-part error |â − a| (stress_norm units) of the predictions of a fixed set of probe
// samples, each predicted with its whole path left out (a neighbouring record of the same path is
// nearly the same interval, so leaving only the sample out would reward scales that find it).
// Search: coordinate descent on ln ℓ_j — multiply ℓ_j by e^{±s}, keep a change that lowers the loss,
// halve s after a sweep without one — for a fixed number of sweeps. Deterministic.
#pragma once
#include <cstddef>
#include <vector>

#include "database/surrogate/surrogate_index.hpp"

namespace grainbank::surrogate {

LengthScales initial_length_scales(const std::vector<Sample>& samples);

struct LengthScaleFit {
  LengthScales scales{};
  double initial_loss = 0, loss = 0;  // before and after the search
  std::size_t evaluations = 0;        // losses computed
};

struct LengthScaleSearch {
  std::size_t probes = 200;  // probe samples, spread evenly over the dataset
  std::size_t sweeps = 4;
  double step = 1.0;         // s of the first sweep (ln units)
};

// The loss of `scales` over `probes` (indices into `samples`).
double leave_path_out_loss(const FeatureConstants& constants, const std::vector<Sample>& samples,
                           const LengthScales& scales, const SurrogateOptions& options,
                           const std::vector<std::size_t>& probes);

// Throws std::invalid_argument when `samples` is empty.
LengthScaleFit fit_length_scales(const FeatureConstants& constants, const std::vector<Sample>& samples,
                                 const SurrogateOptions& options, const LengthScaleSearch& search = {});

}  // namespace grainbank::surrogate
