// Restart files (HDF5): everything that evolves during a run — time, step count, every material
// point, the obstacles' contact history, the full state of every live DEM cell and what
// the points of cache/hybrid laws carry (damage, steps inside the tolerance, replay history) — so
// that a solver built from the same scene and restored continues exactly like the uninterrupted run.
// Layout: attributes format (kRestartFormat), time, steps, kinetic_energy_peak, kinetic_energy_peak_since; dataset points (one row per point, see restart.cpp); dataset
// obstacle_tangential and obstacle_held (obstacles × points; the normal force each point had when a
// gradual release began, NaN before it; absent in older files); group law_<i>_cell_<slot> per live cell (as in the
// library's cell snapshots, database/SCHEMA.md); datasets law_<i>_library_points and
// law_<i>_replay_history per cache/hybrid law.
#pragma once
#include <cstddef>
#include <filesystem>

#include "mpm_solver/core/solver.hpp"

namespace grainbank::mpm::io {

// The layout's version, written into every file; a file of another version is refused.
// 2: points of cache/hybrid laws also carry their steps inside the tolerance and replay history.
// 3: a point's pending increment has its elapsed time; increments carry L; cache/hybrid points no
//    longer carry an F of their own; points carry APIC's affine velocity B_p.
// 4: the surrogate's learned samples carry the pressure feature that tells tension apart
//    (state_features.hpp); keys written before meant another thing below p_floor.
// 5: the surrogate law keeps each point's checkpoint (its last cell started by replay) and whether
//    its live cell is one; the error spent counts since the last live spell.
// 6: the surrogate law keeps whether a point's live spell was started by its spent error budget.
// 7: the surrogate law keeps how many increments a point's kept cell has seen (its next start catches
//    the cell up on the rest), no longer the point's state when it kept the cell.
inline constexpr const char* kRestartFormat = "grainbank-restart-7";
// Columns of a row of the dataset `points` (one row per point; restart.cpp lists them).
inline constexpr std::size_t kRestartPointColumns = 33;

// What the run itself has seen, beyond the solver's state: kept so that a resumed run judges as the
// uninterrupted one would (attributes kinetic_energy_peak and kinetic_energy_peak_since). A file of
// an older build has no peak: the resumed run counts its peak from the resumed time, and says so.
struct RunRecord {
  double kinetic_energy_peak = 0;        // the largest kinetic energy of any series row so far [J/m]
  double kinetic_energy_peak_since = 0;  // the time from which that peak was counted [s]
};

void write_restart(const std::filesystem::path& file, const Solver& solver, const RunRecord& run = {});

// `solver` must come from the same scene (same laws, obstacles and number of points); throws
// std::runtime_error naming the file otherwise. Returns the run's record.
RunRecord read_restart(const std::filesystem::path& file, Solver& solver);

}  // namespace grainbank::mpm::io
