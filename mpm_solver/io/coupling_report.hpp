// What the library-backed laws did during a run, for its outputs: the per-step picture of the
// points (CSV series columns) and the run totals (summary JSON). Also ends the run for the laws
// (finish: enriched paths are marked done).
#pragma once
#include <nlohmann/json.hpp>

#include "core/solver.hpp"

namespace grainbank::mpm::io {

// The points by source of their last stress, at the current step.
struct StepCoupling {
  long hits = 0, misses = 0, live = 0, analytic = 0;
  double mean_estimated_error = 0;  // over points answered by the library [Pa]
  double hit_rate() const { return hits + misses ? double(hits) / double(hits + misses) : 0.0; }
};
StepCoupling step_coupling(const Solver& solver);

// Calls finish() on every law, then returns the totals: per law (name, counters, hit rate, mean
// estimated error), the point-steps that skipped the constitutive call and all point-steps.
nlohmann::json finish_coupling(Solver& solver);

}  // namespace grainbank::mpm::io
