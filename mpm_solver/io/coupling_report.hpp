// What the library-backed laws did during a run, for its outputs: the per-step picture of the
// points (CSV series columns) and the run totals (summary JSON).
#pragma once
#include <nlohmann/json.hpp>
#include <optional>

#include "mpm_solver/core/dem_backed_law.hpp"
#include "mpm_solver/core/solver.hpp"

namespace grainbank::mpm::io {

// The points by source of their last stress, at the current step.
struct StepCoupling {
  long hits = 0, misses = 0, live = 0, analytic = 0;
  double mean_estimated_error = 0;  // over points answered by the library [Pa]
  double hit_rate() const { return hits + misses ? double(hits) / double(hits + misses) : 0.0; }
};
StepCoupling step_coupling(const Solver& solver);

// The counters of the points of law `law` (all laws: nullopt), summed.
CouplingCounters coupling_counters(const Solver& solver, std::optional<std::size_t> law = std::nullopt);

// The run's totals: per law (name, counters, hit rate, mean estimated error, and the figures of its
// start report nested at each '/'), the point-steps that skipped the constitutive call and all
// point-steps. After Solver::finish, they include what the
// laws wrote at the end.
nlohmann::json coupling_summary(const Solver& solver);

}  // namespace grainbank::mpm::io
