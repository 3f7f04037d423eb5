// One sample of the state-keyed surrogate: the key of a state under a loading and what it answered.
// A library gives one per recorded interval (reindex.hpp); a live point or cell, one per step.
#pragma once
#include <cstdint>

#include "database/surrogate/rate_answer.hpp"
#include "database/surrogate/state_features.hpp"

namespace grainbank::surrogate {

// Where a sample came from: the interval from record `record_index` to the next one of library path
// `path_id`. Samples added during a run use negative path ids, one per source (a point, a cell).
struct SampleOrigin {
  std::int64_t path_id = 0;
  std::int64_t record_index = 0;
  bool operator==(const SampleOrigin&) const = default;
};

struct Sample {
  FeatureVector features{};  // feature_vector(state_features(before, L))
  Answer answer{};           // rate_answer(before, after, L, Δt)
  SampleOrigin origin;
};

// The sample of one interval; throws std::invalid_argument as rate_answer does.
Sample make_sample(const PointState& before, const PointState& after, const dem::Mat3& L, double dt,
                   const FeatureConstants& constants, SampleOrigin origin);

}  // namespace grainbank::surrogate
