// Cell preparation (DESIGN.md, "Preparation"): polydisperse random gas -> isotropic compression under
// stress control to p_0 (friction may be lowered to control density) -> relaxation -> bonding of
// close pairs -> relaxation -> a check that the template, left alone without the preparation's
// damping and servo, stays in equilibrium. Fully determined by the spec, including its seed.
#pragma once
#include <cstdint>
#include <functional>
#include <string>

#include "dem_sampler/cell/dem_cell.hpp"

namespace grainbank::dem {

struct PreparationSpec {
  std::size_t spheres = 125;
  double min_diameter = 0, max_diameter = 0;  // diameters uniform in [min, max] [m]
  double pressure = 0;                        // p_0 [Pa]
  double initial_solid_fraction = 0.25;       // of the random gas
  double compression_friction = 0;            // μ while compressing (lower = denser)
  double pressure_tolerance = 0.02;           // |p - p_0| / p_0
  double unbalanced_force_tolerance = 0.02;   // mean |net force| / mean |pair force|
  double inertial_number = 1e-3;              // caps the servo strain rate: I = L d sqrt(ρ/p_0)
  double local_damping = 0.3;                 // Cundall damping while preparing
  double q_t = 0.1;                           // time-step factor of seed Eq. 3
  double skin = 0.1;                          // Verlet skin as a fraction of the mean diameter
  std::uint64_t seed = 1;
  long max_steps = 5'000'000;                 // per stage
  // The equilibrium check: the template is held at fixed volume, undamped, for equilibrium_hold
  // inertial times d sqrt(ρ/p_0) and refused if its pressure moves by more than equilibrium_drift p_0.
  // Neither changes the cell, so neither is part of a template's identity.
  double equilibrium_hold = 20;
  double equilibrium_drift = 0.05;
};

struct PreparationReport {
  long compression_steps = 0, relaxation_steps = 0;
  std::int64_t bonds = 0;
  CellMeasures final;
};

// Called now and then with the stage name ("compression", "relaxation"), the step count and the
// current measures; lets a CLI show progress without the engine knowing about terminals.
using PreparationObserver = std::function<void(const std::string& stage, long step, const CellMeasures&)>;

// Throws std::invalid_argument for an inconsistent spec and std::runtime_error (with the stage, the
// quantity and what to change) when a stage does not converge within max_steps or the template is
// not in equilibrium once left alone.
DemCell prepare_cell(const Material& material, const PreparationSpec& spec, PreparationReport* report = nullptr,
                     const PreparationObserver& observer = {});

// The equilibrium check's hold in seconds: spec.equilibrium_hold inertial times d̄ sqrt(ρ/p_0), the
// time scale on which a packing held up only by damping collapses.
double equilibrium_hold_seconds(const Material& material, const PreparationSpec& spec);

// The largest change of the cell's pressure, over p_ref, while a copy of it is held at fixed volume
// (L = 0, no damping) for `duration` seconds, in steps of Q_t (seed Eq. 3). A packing that only the
// preparation's damping and servo held up collapses here.
double pressure_drift_at_rest(const DemCell& cell, double duration, double q_t, double p_ref);

// The random gas alone (for tests and for packings made elsewhere): cubic cell, no overlaps.
DemCell random_gas(const Material& material, const PreparationSpec& spec);

// Mean pressure p = -tr(σ)/3 of a tension-positive stress.
inline double pressure_of(const Mat3& stress) { return -stress.trace() / 3; }

}  // namespace grainbank::dem
