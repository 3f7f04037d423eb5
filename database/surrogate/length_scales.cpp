#include "database/surrogate/length_scales.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

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

double leave_path_out_loss(const FeatureConstants& constants, const std::vector<Sample>& samples,
                           const LengthScales& scales, const SurrogateOptions& options,
                           const std::vector<std::size_t>& probes) {
  SurrogateIndex index(constants, scales, options);
  index.insert(samples);
  double loss = 0;
  for (const std::size_t i : probes) {
    const Sample& s = samples[i];
    const Answer predicted = index.predict_without(s.features, {s.origin.path_id, std::nullopt}).fit.answer;
    Answer difference;
    for (std::size_t c = 0; c < kAnswerSize; ++c) difference[c] = predicted[c] - s.answer[c];
    loss += stress_norm(difference);
  }
  return loss / static_cast<double>(probes.size());
}

LengthScaleFit fit_length_scales(const FeatureConstants& constants, const std::vector<Sample>& samples,
                                 const SurrogateOptions& options, const LengthScaleSearch& search) {
  if (samples.empty()) throw std::invalid_argument("length scales: no samples to fit them on");
  const std::vector<std::size_t> probes = probe_indices(samples.size(), search.probes, search.seed);

  LengthScaleFit fit;
  fit.scales = initial_length_scales(samples);
  fit.initial_loss = fit.loss = leave_path_out_loss(constants, samples, fit.scales, options, probes);
  fit.evaluations = 1;
  double step = search.step;
  for (std::size_t sweep = 0; sweep < search.sweeps; ++sweep) {
    bool improved = false;
    for (std::size_t j = 0; j < kFeatureCount; ++j) {
      for (const double factor : {std::exp(step), std::exp(-step)}) {
        LengthScales trial = fit.scales;
        trial[j] *= factor;
        const double loss = leave_path_out_loss(constants, samples, trial, options, probes);
        ++fit.evaluations;
        if (loss < fit.loss) {
          fit.loss = loss;
          fit.scales = trial;
          improved = true;
          break;
        }
      }
    }
    if (!improved) step /= 2;
  }
  return fit;
}

}  // namespace grainbank::surrogate
