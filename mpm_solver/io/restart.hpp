// Restart files (HDF5): everything that evolves during a run — time, step count, every material
// point, the obstacles' tangential contact history, the full state of every live DEM cell and what
// the points of cache/hybrid laws carry (F, damage, steps inside the tolerance, replay history) — so
// that a solver built from the same scene and restored continues exactly like the uninterrupted run.
// Layout: attributes format ("grainbank-restart-3"), time, steps; dataset points (one row per point, see restart.cpp); dataset
// obstacle_tangential (obstacles × points); group law_<i>_cell_<slot> per live cell (as in the
// library's cell snapshots, database/SCHEMA.md); datasets law_<i>_library_points and
// law_<i>_replay_history per cache/hybrid law.
#pragma once
#include <filesystem>

#include "core/solver.hpp"

namespace grainbank::mpm::io {

void write_restart(const std::filesystem::path& file, const Solver& solver);

// `solver` must come from the same scene (same laws, obstacles and number of points); throws
// std::runtime_error naming the file otherwise.
void read_restart(const std::filesystem::path& file, Solver& solver);

}  // namespace grainbank::mpm::io
