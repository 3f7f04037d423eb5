// Regeneration (issue 15): a cell that keeps flattening after re-tiling has reached its cap cannot be
// doubled again; rather than stop the run, it is replaced by a fresh cell of the same material
// brought to the worn cell's state. This is an approximation, not an identity like re-tiling: the
// fresh cell carries the worn one's stress, damage and deformation gradient, but not its fabric,
// contact history or solid fraction.
//
// Promises:
// - Damage (seed Eq. 6): the fresh cell keeps round((1 − D) N_b(0)) of its bonds, D the worn cell's
//   damage and N_b(0) the fresh cell's initial count. The bonds that break are those whose branch
//   carries the most tensile normal stress n·σn of the worn cell (ties: the earlier pair), the
//   direction in which a loaded bonded packing loses its bonds; under isotropic stress the choice is
//   by pair order. A fresh cell already more damaged than the worn one keeps its bonds.
// - Stress: the stress servo (stress_servo.hpp) brings the fresh cell to the symmetric part of the
//   worn cell's last measured stress, within `tolerance_fraction` of the stress scale, at inertial
//   number `inertial_number` at that scale. The scale is the target's largest component, but no less
//   than `scale_floor` of the fresh cell's: a worn cell near the free surface carries almost no
//   stress, and a tolerance of a few per cent of nothing is below a small cell's noise. The outcome
//   says whether the servo converged; an unconverged cell is left where the servo stopped.
// - Deformation: the fresh cell's reference is set so that F = h h_ref⁻¹ is the worn cell's F, so
//   whoever follows a material's volume through F sees no jump.
// - The cell's clock continues from the worn cell's. Deterministic: no random choice.
#pragma once
#include <cstdint>

#include "dem_sampler/cell/dem_cell.hpp"
#include "dem_sampler/cell/stress_servo.hpp"

namespace grainbank::dem {

struct RegenerationSettings {
  double tolerance_fraction = 0.05;  // servo tolerance per stress component, relative to the stress scale
  double scale_floor = 0.1;          // the scale is at least this fraction of the fresh cell's stress
  double inertial_number = 1e-3;     // servo rate |L| ≤ I √(σ/ρ_s) / d: quasi-static
  long max_servo_steps = 20000;      // DEM steps
  double q_t = 0.1;                  // DEM time step factor of seed Eq. 3
};

struct Regeneration {
  DemCell cell;
  std::int64_t bonds_broken = 0;
  StressServoResult servo;
};

// `fresh` is a state of the worn cell's material (its template). Throws std::invalid_argument on bad
// settings.
Regeneration regenerate(const DemCell& worn, CellState fresh, const RegenerationSettings& settings);

// Breaks intact bonds of `state`, the most tensile n·σn first (σ tension-positive), until `keep`
// remain; returns how many broke. The state's forces are left as they were: they belong to the
// bonded packing until the next step recomputes them.
std::int64_t break_most_tensile_bonds(CellState& state, const Mat3& stress, std::int64_t keep);

}  // namespace grainbank::dem
