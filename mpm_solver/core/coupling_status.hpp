// What answered a material point's stress, and the counters of the DEM-backed laws (live, cache,
// hybrid, surrogate): written to the CSV series, the VTU fields and the run summary.
#pragma once
#include <cstdint>

namespace grainbank::mpm {

// Where the last stress of a point came from. The values are written to VTU files: keep them.
enum class StressSource : std::int32_t {
  analytic = 0,  // an analytic law (elastic, Drucker–Prager)
  live = 1,      // its own live DEM cell
  hit = 2,       // the library, nearest record within the tolerance
  miss = 3,      // the library, nearest record beyond the tolerance (cache law: answered anyway)
};

// Cumulative over a run, summed over the points of a law.
struct CouplingCounters {
  std::uint64_t hits = 0, misses = 0;   // lookups answered within / beyond the tolerance
  std::uint64_t live_updates = 0;       // point-steps computed by a live cell of a hybrid point
  std::uint64_t went_live = 0;          // hybrid points that turned live (warm start or replay)
  std::uint64_t went_live_on_budget = 0;  // of those, surrogate points sent live by a spent error budget (replay)
  std::uint64_t reanchored = 0;  // surrogate points re-anchored on a servoed cell by a spent error budget
  std::uint64_t returned_to_cache = 0;  // live points handed back to the cache (hysteresis)
  std::uint64_t warm_start_increments = 0;  // DEM increments run to bring new live cells to their F
  std::uint64_t warm_start_servo_steps = 0;  // DEM steps of the stress servo of state warm starts
  std::uint64_t servo_unconverged = 0;       // state warm starts whose servo did not reach the point's stress
  std::uint64_t warm_start_catch_up_steps = 0;  // DEM steps driving points' own cells through their motion since kept
  double warm_start_seconds = 0;            // wall time of building those cells [s]
  double estimated_error_sum = 0;           // Σ over lookups of the lookup's estimated error [Pa]
  std::uint64_t enriched_paths = 0, enriched_records = 0;  // written to the run's own shard
  std::uint64_t retilings = 0;              // doublings of live cells (dem_sampler/cell/retiling.hpp)
  std::uint64_t regenerations = 0;          // live cells replaced past the re-tiling cap (cell/regeneration.hpp)
  std::uint64_t regenerations_unconverged = 0;  // of those, the ones whose servo missed the worn cell's stress
  std::uint64_t dispersed_holds = 0;  // dilating increments a dispersed cell did not take (live_cell_model.hpp)

  CouplingCounters& operator+=(const CouplingCounters& o) {
    hits += o.hits, misses += o.misses, live_updates += o.live_updates, went_live += o.went_live;
    went_live_on_budget += o.went_live_on_budget, reanchored += o.reanchored;
    returned_to_cache += o.returned_to_cache, warm_start_increments += o.warm_start_increments;
    warm_start_servo_steps += o.warm_start_servo_steps, servo_unconverged += o.servo_unconverged;
    warm_start_catch_up_steps += o.warm_start_catch_up_steps;
    warm_start_seconds += o.warm_start_seconds, estimated_error_sum += o.estimated_error_sum;
    enriched_paths += o.enriched_paths, enriched_records += o.enriched_records, retilings += o.retilings;
    regenerations += o.regenerations, regenerations_unconverged += o.regenerations_unconverged;
    dispersed_holds += o.dispersed_holds;
    return *this;
  }
  double hit_rate() const { return hits + misses ? double(hits) / double(hits + misses) : 0.0; }
};

}  // namespace grainbank::mpm
