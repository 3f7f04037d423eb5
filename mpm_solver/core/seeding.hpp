// Filling a region of the grid with material points: n × n points per cell at the centres of the
// sub-cells, kept when inside the region. Each point gets the volume (h/n)² and, for obstacle
// contact, the disk radius h/(2n).
#pragma once
#include "mpm_solver/core/geometry.hpp"
#include "mpm_solver/core/solver.hpp"

namespace grainbank::mpm {

// A rectangle [lower, upper] as a closed polygon.
Polyline rectangle(const Vec2& lower, const Vec2& upper);

// Adds the points of `region` (a closed polygon) with law `law` and initial velocity; returns their
// count. Throws std::invalid_argument for points_per_cell < 1 or a region reaching outside the grid.
std::size_t seed_region(Solver& solver, std::size_t law, const Polyline& region, int points_per_cell,
                        const Vec2& velocity = Vec2::Zero());

}  // namespace grainbank::mpm
