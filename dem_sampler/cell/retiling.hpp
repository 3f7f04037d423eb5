// Re-tiling: a periodic cell h and its supercell h M (M integer, det M = 2, doubling one cell vector)
// describe the same infinite packing. Lattice reduction (periodic_cell.hpp) keeps a sheared cell
// compact, but a cell stretched one way and flattened the other has a thin width no basis change can
// widen; doubling the thin vector doubles that width, with every sphere, Verlet pair, contact
// history, bond and rolling moment appearing twice. The stress, the measures per sphere and the
// deformation gradient F = h h_ref⁻¹ are unchanged; only the spheres per cell double.
#pragma once
#include "dem_sampler/cell/cell_state.hpp"

namespace grainbank::dem {

// The cell vector (column of h) whose perpendicular width is the smallest.
int thinnest_axis(const Mat3& h);

// `state` described by the supercell whose cell vector `axis` is doubled. Sphere p keeps its index
// and its copy, one old cell vector further along `axis`, is p + N. `state` must carry its Verlet
// list (not a fresh state); throws std::invalid_argument otherwise or on an axis outside 0..2.
CellState doubled_along(const CellState& state, int axis);

}  // namespace grainbank::dem
