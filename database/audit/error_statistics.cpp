#include "database/audit/error_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace grainbank::audit {

double stress_norm(const db::Stress6& s) {
  return std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2] + 2 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]));
}

double relative_stress_error(const db::Stress6& answer, const db::Stress6& truth, double floor) {
  db::Stress6 difference;
  for (std::size_t i = 0; i < difference.size(); ++i) difference[i] = answer[i] - truth[i];
  const double scale = std::max(stress_norm(truth), floor);
  const double error = stress_norm(difference);
  // Only an all-zero library has no scale: then any difference is infinitely wrong.
  return scale > 0 ? error / scale : (error > 0 ? std::numeric_limits<double>::infinity() : 0.0);
}

double quantile(std::vector<double> values, double q) {
  if (values.empty()) throw std::invalid_argument("quantile of an empty sample");
  std::sort(values.begin(), values.end());
  const double position = q * static_cast<double>(values.size() - 1);
  const auto below = static_cast<std::size_t>(std::floor(position));
  const std::size_t above = std::min(below + 1, values.size() - 1);
  const double weight = position - static_cast<double>(below);
  return values[below] + weight * (values[above] - values[below]);
}

ErrorSummary summarize(const std::vector<double>& errors) {
  if (errors.empty()) return {};
  return {errors.size(), quantile(errors, 0.5), quantile(errors, 0.95),
          *std::max_element(errors.begin(), errors.end())};
}

namespace {

std::vector<double> errors_of(std::vector<DistanceError>::const_iterator first,
                              std::vector<DistanceError>::const_iterator last) {
  std::vector<double> errors;
  for (auto it = first; it != last; ++it) errors.push_back(it->error);
  return errors;
}

}  // namespace

std::vector<DistanceBin> bin_by_distance(std::vector<DistanceError> answers, std::size_t bins,
                                         std::size_t min_per_bin) {
  if (answers.empty()) return {};
  std::sort(answers.begin(), answers.end(),
            [](const DistanceError& a, const DistanceError& b) { return a.distance < b.distance; });
  const std::size_t count = std::clamp<std::size_t>(answers.size() / std::max<std::size_t>(min_per_bin, 1), 1,
                                                    std::max<std::size_t>(bins, 1));
  std::vector<DistanceBin> out;
  for (std::size_t b = 0; b < count; ++b) {
    const auto first = answers.begin() + static_cast<std::ptrdiff_t>(b * answers.size() / count);
    const auto last = answers.begin() + static_cast<std::ptrdiff_t>((b + 1) * answers.size() / count);
    out.push_back({first->distance, std::prev(last)->distance, summarize(errors_of(first, last))});
  }
  return out;
}

HitErrors hits_at(const std::vector<DistanceError>& answers, double tolerance) {
  std::vector<double> hits;
  for (const DistanceError& a : answers)
    if (a.distance <= tolerance) hits.push_back(a.error);
  const double share = answers.empty() ? 0 : static_cast<double>(hits.size()) / static_cast<double>(answers.size());
  return {tolerance, share, summarize(hits)};
}

std::optional<HitErrors> suggest_tolerance(const std::vector<DistanceError>& answers,
                                           const std::vector<DistanceBin>& bins, double target) {
  std::optional<HitErrors> best;
  for (const DistanceBin& bin : bins) {
    const HitErrors candidate = hits_at(answers, bin.distance_max);
    if (candidate.hits.p95 <= target) best = candidate;
  }
  return best;
}

}  // namespace grainbank::audit
