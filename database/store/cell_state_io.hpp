// dem::CellState <-> HDF5 group. Every field is stored at full precision, so a cell rebuilt from a
// stored state continues bit-for-bit like the original. Layout (see SCHEMA.md): 3×3 matrices and
// per-sphere / per-pair arrays as datasets, scalars as attributes of the group.
#pragma once
#include "dem_sampler/cell/cell_state.hpp"
#include "database/store/hdf5_handle.hpp"

namespace grainbank::db {

// What it takes to rebuild a DemCell besides the material: the state and the Verlet skin.
struct StoredCell {
  dem::CellState state;
  double skin = 0;  // [m]
};

void write_cell_state(const h5::Object& group, const StoredCell& cell);

// Throws StoreError naming the file and group when a field is missing or has inconsistent length.
StoredCell read_cell_state(const h5::Object& group);

}  // namespace grainbank::db
