// Bringing a cell to a prescribed stress (issue 13, item 3): a live fallback warm-started from a
// stored cell whose state is only near the material point's must carry the point's stress before it
// is coupled, or the MPM would see a jump.
//
// Every component of the velocity gradient is servo-controlled on the symmetric part of the cell's
// stress (the Love–Weber stress is symmetric only at equilibrium of moments):
// L = clamp(max_rate (σ* − sym σ) / stress_scale, ±max_rate) componentwise. The target is
// symmetric, so L is a pure stretching and the cell does not turn.
//
// Promises:
// - Converged means: the mean of sym σ over the last `window` steps is within `tolerance` of the
//   target in every component, at a check after at least `window` steps. The instantaneous stress
//   of a small cell fluctuates with its grains' motion, so single steps are not trusted.
// - It gives up after max_steps, or after `patience` windows without progress (a target the packing
//   cannot carry). The cell is left where the servo stopped; the caller decides what to do with a
//   failure (the result says how far it got).
// - Throws std::invalid_argument on a non-finite or asymmetric target or non-positive settings, and
//   std::runtime_error if the cell's stress becomes non-finite.
#pragma once
#include "dem_sampler/cell/dem_cell.hpp"

namespace grainbank::dem {

struct StressServoSettings {
  double tolerance = 0;     // [Pa] per component, on the windowed mean
  double stress_scale = 0;  // [Pa] stress error that drives the cell at max_rate
  double max_rate = 0;      // [1/s] largest strain rate of a component
  double dt = 0;            // [s] DEM time step
  long window = 50;         // steps averaged for the check (and between checks)
  long max_steps = 0;
  // Windows in a row that do not lower the best residual by 5 % before the servo gives up: a target
  // beyond what the packing can carry (past its yield surface) is chased at full rate forever.
  long patience = 20;
};

struct StressServoResult {
  bool converged = false;
  long steps = 0;
  double residual = 0;  // [Pa] largest component of (windowed mean of sym σ − target) at the last check
};

StressServoResult servo_to_stress(DemCell& cell, const Mat3& target, const StressServoSettings& settings);

}  // namespace grainbank::dem
