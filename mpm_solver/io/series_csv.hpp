// CSV outputs of a run: the time series of global measures and the history of tracked points.
// Full precision, one header line, comma-separated; every write() is on disk when it returns.
#pragma once
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <vector>

#include "mpm_solver/core/diagnostics.hpp"
#include "mpm_solver/core/solver.hpp"

namespace grainbank::mpm::io {

// Columns: t, dt (the last step), step, kinetic_energy, front, max_height, max_velocity, the
// time-step criteria of the next step: limit_wave (CFL), limit_contact, limit_law (seed Eq. 4), and
// the coupling of the last step: points answered by a library hit, by a miss, by a live cell,
// hit_rate (hits / lookups), mean_estimated_error [Pa] of the lookups; then cumulative counts:
// went_live (points that turned live), warm_start_time [s] and skipped_point_steps.
class SeriesCsv {
 public:
  explicit SeriesCsv(const std::filesystem::path& file);
  // `limits` are the solver's time_step_limits() now (a collective call on several ranks, so the
  // caller makes it); returns the flow measures of the row (diagnostics.hpp).
  FlowMeasures write(const Solver& solver, double last_dt, const TimeStepLimits& limits);

 private:
  std::ofstream out_;
};

// Columns: t, point, x, y, vx, vy, sxx, syy, sxy, szz, p, q, strain_rate_q, damage, density.
class TrackedCsv {
 public:
  TrackedCsv(const std::filesystem::path& file, std::vector<std::uint32_t> ids);
  void write(const Solver& solver);

 private:
  std::ofstream out_;
  std::vector<std::uint32_t> ids_;
};

}  // namespace grainbank::mpm::io
