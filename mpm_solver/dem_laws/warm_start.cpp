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

long replay(dem::DemCell& cell, const std::vector<KinematicIncrement>& history, const LiveCellModel& model) {
  for (const KinematicIncrement& increment : history) model.advance(cell, increment);
  return static_cast<long>(history.size());
}

}  // namespace grainbank::mpm
