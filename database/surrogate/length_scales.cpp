#include "database/surrogate/length_scales.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "database/surrogate/estimate_audit.hpp"

namespace grainbank::surrogate {

LengthScales initial_length_scales(const std::vector<Sample>& samples) {
  LengthScales scales;
  scales.fill(1);
  if (samples.size() < 2) return scales;
  const double n = static_cast<double>(samples.size());
  for (std::size_t j = 0; j < kFeatureCount; ++j) {
    double mean = 0, square = 0;
    for (const Sample& s : samples) mean += s.features[j] / n;
    for (const Sample& s : samples) square += (s.features[j] - mean) * (s.features[j] - mean) / (n - 1);
    const double deviation = std::sqrt(square);
    if (deviation > 1e-12 * (1 + std::abs(mean))) scales[j] = deviation;
  }
  return scales;
}

std::vector<std::size_t> probe_indices(std::size_t samples, std::size_t count, std::uint64_t seed) {
  count = std::min(count, samples);
  const double golden = (std::sqrt(5.0) - 1) / 2;
  const double shift = std::fmod(static_cast<double>(seed) * golden, 1.0);
  std::vector<std::size_t> probes;
  for (std::size_t i = 0; i < count; ++i)
    probes.push_back(static_cast<std::size_t>((static_cast<double>(i) + shift) * static_cast<double>(samples) /
                                              static_cast<double>(count)));
  return probes;
}

namespace {

std::vector<PredictionOutcome> predict_probes(const FeatureConstants& constants, const std::vector<Sample>& samples,
                                         const LengthScales& scales, const SurrogateOptions& options,
                                         const std::vector<std::size_t>& probes) {
  SurrogateIndex index(constants, scales, options);
  index.insert(samples);
  std::vector<PredictionOutcome> outcomes;
  outcomes.reserve(probes.size());
  for (const std::size_t i : probes) {
    const Sample& s = samples[i];
    outcomes.push_back(outcome_of(index.predict_without(s.features, {s.origin.path_id, std::nullopt}), s));
  }
  return outcomes;
}

double mean(const std::vector<double>& values) {
  double sum = 0;
  for (const double v : values) sum += v;
  return sum / static_cast<double>(values.size());
}

// Mean of `trial` − `fitted` over its standard error (0 when every difference is 0).
double paired_change(const std::vector<double>& trial, const std::vector<double>& fitted) {
  std::vector<double> differences;
  for (std::size_t i = 0; i < fitted.size(); ++i) differences.push_back(trial[i] - fitted[i]);
  if (differences.size() < 2) return 0;
  const double n = static_cast<double>(differences.size()), average = mean(differences);
  double square = 0;
  for (const double d : differences) square += (d - average) * (d - average);
  const double standard_error = std::sqrt(square / (n - 1) / n);
  return standard_error > 0 ? average / standard_error : 0;
}

std::vector<double> errors_of(const std::vector<PredictionOutcome>& outcomes) {
  std::vector<double> errors;
  for (const PredictionOutcome& probe : outcomes) errors.push_back(probe.error);
  return errors;
}

}  // namespace

double leave_path_out_loss(const FeatureConstants& constants, const std::vector<Sample>& samples,
                           const LengthScales& scales, const SurrogateOptions& options,
                           const std::vector<std::size_t>& probes) {
  return mean(errors_of(predict_probes(constants, samples, scales, options, probes)));
}

LengthScaleFit fit_length_scales(const FeatureConstants& constants, const std::vector<Sample>& samples,
                                 const SurrogateOptions& options, const LengthScaleSearch& search) {
  if (samples.empty()) throw std::invalid_argument("length scales: no samples to fit them on");
  const std::vector<std::size_t> probes = probe_indices(samples.size(), search.probes, search.seed);

  LengthScaleFit fit;
  fit.probes = probes.size();
  fit.scales = initial_length_scales(samples);
  // The probes' outcomes at the fit's scales, kept from the search for the evidence and calibration.
  std::vector<PredictionOutcome> fitted = predict_probes(constants, samples, fit.scales, options, probes);
  const std::vector<double> initial = errors_of(fitted);
  fit.initial_loss = fit.loss = mean(initial);
  fit.evaluations = 1;
  double step = search.step;
  for (std::size_t sweep = 0; sweep < search.sweeps; ++sweep) {
    bool improved = false;
    for (std::size_t j = 0; j < kFeatureCount; ++j) {
      for (const double factor : {std::exp(step), std::exp(-step)}) {
        LengthScales trial = fit.scales;
        trial[j] *= factor;
        std::vector<PredictionOutcome> outcomes = predict_probes(constants, samples, trial, options, probes);
        const double loss = mean(errors_of(outcomes));
        ++fit.evaluations;
        if (loss < fit.loss) {
          fit.loss = loss;
          fit.scales = trial;
          fitted = std::move(outcomes);
          improved = true;
          break;
        }
      }
    }
    if (!improved) step /= 2;
  }
  const std::vector<double> errors = errors_of(fitted);
  std::vector<double> estimates;
  for (const PredictionOutcome& probe : fitted) estimates.push_back(probe.estimate);
  const EstimateCalibration calibration = calibration_of(errors, estimates);
  fit.coverage = calibration.coverage;
  fit.median_error_over_estimate = calibration.median_error_over_estimate;
  fit.gain = paired_change(initial, errors);
  for (std::size_t j = 0; j < kFeatureCount; ++j) {
    const auto change = [&](double factor) {
      LengthScales trial = fit.scales;
      trial[j] *= factor;
      ++fit.evaluations;
      return paired_change(errors_of(predict_probes(constants, samples, trial, options, probes)), errors);
    };
    fit.evidence[j] = {change(std::exp(-1.0)), change(std::exp(1.0))};
  }
  return fit;
}

}  // namespace grainbank::surrogate
