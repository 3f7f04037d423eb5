#include "mpm_solver/dem_laws/warm_start.hpp"

#include <cmath>

#include "dem_sampler/cell/matrix_functions.hpp"

namespace grainbank::mpm {

long drive_to(dem::DemCell& cell, const dem::Mat3& target, double max_strain, double dt, const dem::Substepping& q) {
  const dem::Mat3 log_g = dem::matrix_logarithm(target * cell.deformation_gradient().inverse());
  // Below round-off of F the cell is already there: driving would only add noise.
  const double size = log_g.norm();
  if (size < 1e-12) return 0;
  const long n = static_cast<long>(std::ceil(size / max_strain));
  const dem::Mat3 step = dem::matrix_exponential(log_g / static_cast<double>(n));
  for (long k = 0; k < n; ++k) cell.advance(step, dt, q);
  return n;
}

long replay(dem::DemCell& cell, const std::vector<KinematicIncrement>& history, const LiveCellModel& model,
            CouplingCounters& counters) {
  for (const KinematicIncrement& increment : history) model.advance(cell, increment, counters);
  return static_cast<long>(history.size());
}

void append_history(std::vector<double>& table, std::size_t slot, const std::vector<KinematicIncrement>& history) {
  for (const KinematicIncrement& r : history)
    table.insert(table.end(), {double(slot), r.F(0, 0), r.F(0, 1), r.F(1, 0), r.F(1, 1), r.L(0, 0), r.L(0, 1), r.L(1, 0),
                               r.L(1, 1), r.dt});
}

std::vector<std::pair<std::size_t, KinematicIncrement>> history_rows(const std::vector<double>& table) {
  std::vector<std::pair<std::size_t, KinematicIncrement>> rows;
  for (std::size_t r = 0; r + kHistoryColumns <= table.size(); r += kHistoryColumns) {
    KinematicIncrement increment;
    increment.F << table[r + 1], table[r + 2], table[r + 3], table[r + 4];
    increment.L << table[r + 5], table[r + 6], table[r + 7], table[r + 8];
    increment.dt = table[r + 9];
    rows.emplace_back(static_cast<std::size_t>(table[r]), increment);
  }
  return rows;
}

}  // namespace grainbank::mpm
