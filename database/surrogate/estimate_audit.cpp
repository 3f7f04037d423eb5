#include "database/surrogate/estimate_audit.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "database/surrogate/length_scales.hpp"

namespace grainbank::surrogate {

namespace {

double median(std::vector<double> values) {
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

}  // namespace

PredictionOutcome outcome_of(const Prediction& predicted, const Sample& truth) {
  Answer difference;
  for (std::size_t c = 0; c < kAnswerSize; ++c) difference[c] = predicted.fit.answer[c] - truth.answer[c];
  return {stress_norm(difference), predicted.fit.stress_error};
}

EstimateCalibration calibration_of(std::span<const double> errors, std::span<const double> estimates) {
  if (errors.size() != estimates.size())
    throw std::invalid_argument("estimate calibration: " + std::to_string(errors.size()) + " errors against " +
                                std::to_string(estimates.size()) + " estimates");
  EstimateCalibration calibration;
  calibration.samples = errors.size();
  if (errors.empty()) return calibration;
  std::vector<double> ratios;
  std::size_t covered = 0;
  for (std::size_t i = 0; i < errors.size(); ++i) {
    ratios.push_back(errors[i] == 0 ? 0.0 : errors[i] / estimates[i]);
    if (errors[i] <= estimates[i]) ++covered;
  }
  calibration.coverage = static_cast<double>(covered) / static_cast<double>(errors.size());
  calibration.median_error_over_estimate = median(std::move(ratios));
  calibration.median_error = median({errors.begin(), errors.end()});
  calibration.median_estimate = median({estimates.begin(), estimates.end()});
  return calibration;
}

EstimateCalibration audit_estimate(const FeatureConstants& constants, const std::vector<Sample>& library,
                                   const LengthScales& scales, const SurrogateOptions& options,
                                   const std::vector<Sample>& states, std::size_t at_most) {
  SurrogateIndex index(constants, scales, options);
  index.insert(library);
  std::vector<double> errors, estimates;
  for (const std::size_t i : probe_indices(states.size(), at_most, 0)) {
    const PredictionOutcome outcome = outcome_of(index.predict(states[i].features), states[i]);
    errors.push_back(outcome.error);
    estimates.push_back(outcome.estimate);
  }
  return calibration_of(errors, estimates);
}

}  // namespace grainbank::surrogate
