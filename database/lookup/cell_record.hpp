// A DEM cell's state after an increment turned into the library's record (store/record.hpp), with its
// state key as the lookup defines it (state_key.hpp), so the stored key column and the index agree.
//
// Promise: the one place a record is built from a cell. The sampler's paths and an MPM run's live
// cells (enrichment) both store what this returns, so a cell driven by either gives the same record.
#pragma once
#include "dem_sampler/cell/dem_cell.hpp"
#include "database/store/key_definition.hpp"
#include "database/store/record.hpp"

namespace grainbank::lookup {

// `L` is the velocity gradient imposed over the increment that ended in this state (zero for an
// initial state) and `stress` the increment's regressed stress (dem::IncrementResult).
db::Record cell_record(const dem::DemCell& cell, const dem::Mat3& L, const dem::Mat3& stress,
                       const db::KeyScales& scales);

}  // namespace grainbank::lookup
