// The optional side of a constitutive law whose points are answered by DEM cells, live or from a
// library of their responses (ConstitutiveLaw::dem_backed). The outputs read it: what answered each
// point (VTU, CSV series, audit trail), the run's counters (summary) and the cells themselves
// (tracked cells).
#pragma once
#include <cstddef>

#include "mpm_solver/core/constitutive_law.hpp"
#include "mpm_solver/core/coupling_status.hpp"

namespace grainbank::dem {
class DemCell;
}

namespace grainbank::mpm {

class DemBackedLaw {
 public:
  virtual ~DemBackedLaw() = default;

  // What answered the last update of `slot`, and the error the library estimates for that answer
  // (0 unless it came from a lookup) [Pa].
  virtual StressSource source(std::size_t slot) const = 0;
  virtual double estimated_error(std::size_t /*slot*/) const { return 0; }
  // Lookups, live cell updates and enrichment of one point so far; a law's totals are their sum.
  virtual CouplingCounters point_counters(std::size_t /*slot*/) const { return {}; }
  // The DEM cell that answers `slot` now, or null (a library answer).
  virtual const dem::DemCell* live_cell(std::size_t slot) const = 0;
};

// What answered the last stress of a point of `law` (analytic for laws without DEM cells).
inline StressSource stress_source(const ConstitutiveLaw& law, std::size_t slot) {
  const DemBackedLaw* dem = law.dem_backed();
  return dem ? dem->source(slot) : StressSource::analytic;
}

}  // namespace grainbank::mpm
