// Statistics of the audit's stress errors (DESIGN.md, "honest error bars on the surrogate"): summaries
// of a sample of errors, errors binned by nearest-record distance, and the lookup tolerance that
// keeps the error of hits within a target. Pure functions of the numbers; no library access.
#pragma once
#include <optional>
#include <vector>

#include "database/store/record.hpp"

namespace grainbank::audit {

// Frobenius norm of a symmetric stress given by its 6 components [Pa].
double stress_norm(const db::Stress6& stress);
// ‖answer − truth‖ / max(‖truth‖, floor): relative to the true stress, with a floor [Pa] so that a
// near-zero true stress (a cell pulled apart) does not turn a small absolute error into a huge one.
double relative_stress_error(const db::Stress6& answer, const db::Stress6& truth, double floor);

struct ErrorSummary {
  std::size_t count = 0;
  double median = 0, p95 = 0, max = 0;  // 0 when count == 0
};

// Quantile q in [0, 1] of `values` by linear interpolation between order statistics (q = 0.5: the
// median of an even count is the mean of the two middle values). Throws std::invalid_argument when
// `values` is empty.
double quantile(std::vector<double> values, double q);
ErrorSummary summarize(const std::vector<double>& errors);

// One lookup answer: nearest-record distance (key units) and the relative error of the answer.
struct DistanceError {
  double distance = 0;
  double error = 0;
};

// Records whose nearest distance lies in [distance_min, distance_max].
struct DistanceBin {
  double distance_min = 0, distance_max = 0;
  ErrorSummary error;
};

// Equal-count bins in order of distance (at most `bins`, each with at least `min_per_bin` answers;
// a single bin when there are fewer), so every bin's median and p95 rest on the same number of
// answers whatever the spread of distances.
std::vector<DistanceBin> bin_by_distance(std::vector<DistanceError> answers, std::size_t bins = 10,
                                         std::size_t min_per_bin = 8);

// The answers that are hits at `tolerance` (distance <= tolerance): their share and their errors.
struct HitErrors {
  double tolerance = 0;
  double hit_share = 0;  // of all answers; 0 when there are none
  ErrorSummary hits;
};
HitErrors hits_at(const std::vector<DistanceError>& answers, double tolerance);

// The largest tolerance among the bins' upper distances whose hits have a p95 error <= target; none
// when even the first bin's hits exceed it.
std::optional<HitErrors> suggest_tolerance(const std::vector<DistanceError>& answers,
                                           const std::vector<DistanceBin>& bins, double target);

}  // namespace grainbank::audit
