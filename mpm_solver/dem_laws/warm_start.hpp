// Bringing a new live cell to a material point's state, when a hybrid point misses (DESIGN.md,
// "Fallback"): either drive a stored cell (the nearest snapshot, or the template) to the point's
// deformation, or replay the point's own recorded increments from the template (exact, slower).
#pragma once
#include <cstddef>
#include <utility>
#include <vector>

#include "mpm_solver/dem_laws/live_cell_model.hpp"

namespace grainbank::mpm {

// Drives `cell` from its deformation gradient F_cell = h h_ref⁻¹ to `target` along the straight
// path in log space: G = target F_cell⁻¹ split into n = ceil(|log G| / max_strain) equal increments
// G^(1/n), each over `dt`. Afterwards F_cell = target up to round-off. Returns n (0 when the cell is
// already there).
long drive_to(dem::DemCell& cell, const dem::Mat3& target, double max_strain, double dt, const dem::Substepping& q);

// Re-runs `history` on `cell` (normally a fresh copy of the template): the cell a point of the live
// law would own after the same increments, counting its re-tilings. Returns the number of increments.
long replay(dem::DemCell& cell, const std::vector<KinematicIncrement>& history, const LiveCellModel& model,
            CouplingCounters& counters);

// The replay histories of a law's points as a restart table (law_state_archive.hpp): rows slot,
// F_inc (4, row-major), L (4), dt, each point's increments in step order.
inline constexpr std::size_t kHistoryColumns = 10;
void append_history(std::vector<double>& table, std::size_t slot, const std::vector<KinematicIncrement>& history);
// The rows of such a table in order, as (slot, increment).
std::vector<std::pair<std::size_t, KinematicIncrement>> history_rows(const std::vector<double>& table);

}  // namespace grainbank::mpm
