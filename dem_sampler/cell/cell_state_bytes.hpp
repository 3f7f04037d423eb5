// A cell's complete state (cell_state.hpp) as bytes and back, bit for bit: how a run spread over MPI
// ranks moves a material point's live cell to the rank that writes the restart file.
#pragma once
#include "common/byte_buffer.hpp"
#include "dem_sampler/cell/cell_state.hpp"

namespace grainbank::dem {

void write_cell_state(const CellState& state, common::ByteWriter& out);
// Throws std::runtime_error when the bytes end early.
CellState read_cell_state(common::ByteReader& in);

}  // namespace grainbank::dem
