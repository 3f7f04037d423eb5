#include "dem_sampler/driver/path_driver.hpp"

#include <cmath>

#include "dem_sampler/cell/matrix_functions.hpp"

namespace grainbank::app {
namespace {

// Relative slack so that a duration that is a multiple of Δt up to round-off gives no sliver step.
constexpr double kSlack = 1e-9;

long segment_increments(const PathSegment& s, double dt) {
  return std::max(1L, static_cast<long>(std::ceil(s.duration / dt * (1 - kSlack))));
}

PathRecord record_of(const dem::DemCell& cell, long index, const dem::Mat3& L, long substeps, const dem::Mat3& stress) {
  PathRecord r;
  r.index = index;
  r.time = cell.time();
  r.F = cell.deformation_gradient();
  r.L = L;
  r.substeps = substeps;
  r.stress = stress;
  r.measures = cell.measures();
  return r;
}

}  // namespace

long increment_count(const PathSpec& path) {
  long n = 0;
  for (const PathSegment& s : path.segments) n += segment_increments(s, path.record_interval);
  return n;
}

void drive_along_path(dem::DemCell& cell, const PathSpec& path,
                      const std::function<void(const PathRecord&)>& on_record, long from_record) {
  long index = 0;
  if (from_record == 0) on_record(record_of(cell, index, dem::Mat3::Zero(), 0, cell.measures().stress));
  for (const PathSegment& segment : path.segments) {
    const long n = segment_increments(segment, path.record_interval);
    const dem::Mat3 full_increment = dem::matrix_exponential(segment.L * path.record_interval);
    for (long k = 1; k <= n; ++k) {
      if (index < from_record) {  // already in the cell we resume from
        ++index;
        continue;
      }
      const double dt =
          k < n ? path.record_interval : segment.duration - static_cast<double>(n - 1) * path.record_interval;
      const dem::Mat3 increment = k < n ? full_increment : dem::matrix_exponential(segment.L * dt);
      const dem::IncrementResult result = cell.advance(increment, dt, path.substepping);
      on_record(record_of(cell, ++index, segment.L, result.substeps, result.stress));
    }
  }
}

}  // namespace grainbank::app
