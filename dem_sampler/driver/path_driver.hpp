// Drives a cell along a path the way a material point of the MPM would: per record interval Δt the
// cell receives the increment F_inc = exp(L Δt) and returns the regressed stress of that increment.
#pragma once
#include <functional>

#include "dem_sampler/cell/dem_cell.hpp"
#include "dem_sampler/driver/path_input.hpp"

namespace grainbank::app {

struct PathRecord {
  long index = 0;         // 0 for the state before the first increment
  double time = 0;        // cell time [s]
  dem::Mat3 F;            // deformation gradient since the cell's reference configuration
  dem::Mat3 L = dem::Mat3::Zero();  // velocity gradient imposed over the increment that ended here
  long substeps = 0;      // DEM steps of that increment (the engine's, dem::IncrementResult)
  dem::Mat3 stress;       // tension-positive [Pa]; regressed over the last Q_σ of the increment
  dem::CellMeasures measures;
};

// Increments of the whole path: each segment takes ceil(duration / Δt) of them, the last one of a
// segment shortened so the segment ends exactly at its duration.
long increment_count(const PathSpec& path);

// Calls `on_record` with the initial state (L zero, no substeps) and after every increment. Engine errors propagate.
// A record's L is the gradient the increment applied: a pressure-controlled segment's (path_input.hpp)
// adds its servo's isotropic stretching to the segment's L.
// With `from_record` = k > 0 the cell is the path's cell right after record k (a snapshot of it): the
// drive resumes there, calling `on_record` for records k+1, ... with the same increments, so they
// repeat the full drive's records bit for bit (what `celldb audit` checks); `resumed_gradient` is
// then record k's L, from which a pressure-controlled segment's servo goes on.
void drive_along_path(dem::DemCell& cell, const PathSpec& path,
                      const std::function<void(const PathRecord&)>& on_record, long from_record = 0,
                      const dem::Mat3& resumed_gradient = dem::Mat3::Zero());

}  // namespace grainbank::app
