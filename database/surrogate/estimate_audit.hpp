// How the surrogate's error estimate compares with the errors it estimates (issue 13: "an honest
// error estimate").
//
// The length-scale fit measures it on its probes, the library's own samples with their paths left
// out (length_scales.hpp). A scene's hardest states are not like those: on the flowing columns of the
// generalization study, at the states where the cells ran live, the estimate covered 26–73 % of the
// library's errors, against 60–81 % on its probes, and the errors were five to ten times larger
// (docs/surrogate.md, "Stop 65"). audit_estimate measures that for a run: the library's answers to
// the samples its live cells learned, which the library does not hold.
//
// Promises:
// - calibration_of(): over pairs (error, estimate) in the same units, the share with error ≤
//   estimate, the median of error/estimate (a pair with no error counts 0, whatever its estimate),
//   and the medians of each; all 0 for no pairs. A median of n values is the ⌊n/2⌋-th smallest.
// - audit_estimate(): each of at most `at_most` of `states` (evenly spaced, as the fit's probes)
//   predicted by an index of `library` alone at `scales`; the error is stress_norm of the predicted
//   answer minus the state's, the estimate the local fit's stress_error (normalized units,
//   local_fit.hpp). Deterministic.
#pragma once
#include <cstddef>
#include <span>
#include <vector>

#include "database/surrogate/surrogate_index.hpp"

namespace grainbank::surrogate {

// A prediction of a sample, against the sample's own answer: the error (stress_norm of the
// difference) and the local fit's estimate of it (stress_error), both in normalized units.
struct PredictionOutcome {
  double error = 0, estimate = 0;
};
PredictionOutcome outcome_of(const Prediction& predicted, const Sample& truth);

struct EstimateCalibration {
  std::size_t samples = 0;
  double coverage = 0;                    // share of samples whose error ≤ the estimate
  double median_error_over_estimate = 0;
  double median_error = 0, median_estimate = 0;
};

// `errors` and `estimates` of equal length; throws std::invalid_argument otherwise.
EstimateCalibration calibration_of(std::span<const double> errors, std::span<const double> estimates);

EstimateCalibration audit_estimate(const FeatureConstants& constants, const std::vector<Sample>& library,
                                   const LengthScales& scales, const SurrogateOptions& options,
                                   const std::vector<Sample>& states, std::size_t at_most);

}  // namespace grainbank::surrogate
