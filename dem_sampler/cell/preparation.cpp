#include "dem_sampler/cell/preparation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "dem_sampler/cell/random.hpp"

namespace grainbank::dem {
namespace {

void check(const PreparationSpec& s, const Material& material) {
  auto fail = [](const char* field, const char* expected, double got) {
    std::ostringstream msg;
    msg << "preparation." << field << ": expected " << expected << ", got " << got;
    throw std::invalid_argument(msg.str());
  };
  if (s.spheres < 2) fail("spheres", "at least 2", static_cast<double>(s.spheres));
  if (!(s.min_diameter > 0)) fail("min_diameter", "a positive number", s.min_diameter);
  if (!(s.max_diameter >= s.min_diameter)) fail("max_diameter", "a number >= min_diameter", s.max_diameter);
  if (!(s.pressure > 0) || !std::isfinite(s.pressure)) fail("pressure", "a positive number", s.pressure);
  if (!(s.initial_solid_fraction > 0 && s.initial_solid_fraction < 0.35))
    fail("initial_solid_fraction", "a number in (0, 0.35) (random gas)", s.initial_solid_fraction);
  if (!(s.compression_friction >= 0)) fail("compression_friction", "a number >= 0", s.compression_friction);
  if (!(s.pressure_tolerance > 0 && s.pressure_tolerance < 1))
    fail("pressure_tolerance", "a number in (0, 1)", s.pressure_tolerance);
  if (!(s.unbalanced_force_tolerance > 0)) fail("unbalanced_force_tolerance", "a positive number", s.unbalanced_force_tolerance);
  if (!(s.inertial_number > 0 && s.inertial_number <= 0.1))
    fail("inertial_number", "a number in (0, 0.1]", s.inertial_number);
  if (!(s.local_damping >= 0 && s.local_damping < 1)) fail("local_damping", "a number in [0, 1)", s.local_damping);
  require_stable_time_step_factor(s.q_t, material.contact.restitution, "preparation.q_t");
  if (!(s.skin > 0 && s.skin <= 1)) fail("skin", "a number in (0, 1]", s.skin);
  if (s.max_steps < 1) fail("max_steps", "a positive number", static_cast<double>(s.max_steps));
  if (!(s.equilibrium_hold >= 0) || !std::isfinite(s.equilibrium_hold))
    fail("equilibrium_hold", "a number >= 0 (inertial times)", s.equilibrium_hold);
  if (!(s.equilibrium_drift > 0)) fail("equilibrium_drift", "a positive number", s.equilibrium_drift);
}

double mean_diameter(const PreparationSpec& s) { return 0.5 * (s.min_diameter + s.max_diameter); }

// Servo-controlled isotropic stress -p_0 with no shear of the cell, until the pressure is within
// tolerance and the spheres are in equilibrium. Returns the number of steps taken.
long settle_at_pressure(DemCell& cell, const Material& material, const PreparationSpec& spec, const std::string& stage,
                        const PreparationObserver& observer) {
  MixedControl control;
  control.stress_controlled.diagonal().setConstant(true);
  control.target_stress = -spec.pressure * Mat3::Identity();
  control.stress_scale = spec.pressure;
  control.max_rate = spec.inertial_number * std::sqrt(spec.pressure / material.density) / mean_diameter(spec);
  const double dt = cell.time_step(spec.q_t);
  constexpr long kCheckEvery = 50;
  int consecutive_ok = 0;
  for (long step = 1; step <= spec.max_steps; ++step) {
    cell.step_mixed(control, dt);
    if (step % kCheckEvery) continue;
    const CellMeasures m = cell.measures();
    if (!m.stress.allFinite()) {
      std::ostringstream msg;
      msg << stage << ": stress became non-finite after " << step
          << " steps (the cell diverged): lower preparation.q_t, or check that material.density, material.k_n "
             "and preparation.pressure are physical";
      throw std::runtime_error(msg.str());
    }
    if (observer && step % (kCheckEvery * 20) == 0) observer(stage, step, m);
    const double p = pressure_of(m.stress);
    const bool ok = std::abs(p - spec.pressure) < spec.pressure_tolerance * spec.pressure &&
                    m.unbalanced_force_ratio < spec.unbalanced_force_tolerance;
    consecutive_ok = ok ? consecutive_ok + 1 : 0;
    if (consecutive_ok >= 3) return step;  // held over three checks, not a passing fluctuation
  }
  const CellMeasures m = cell.measures();
  std::ostringstream msg;
  msg << stage << " did not converge in " << spec.max_steps << " steps: pressure " << pressure_of(m.stress)
      << " Pa (target " << spec.pressure << " Pa), unbalanced force ratio " << m.unbalanced_force_ratio
      << " (target < " << spec.unbalanced_force_tolerance
      << "). Raise preparation.max_steps, preparation.local_damping or the tolerances.";
  throw std::runtime_error(msg.str());
}

// A loosely jammed packing, its frictional contacts near sliding, can pass the relaxation's test with
// the damping on and collapse once it is off: a 125-sphere cell compressed at μ = 0.5 to 1 kPa lost
// 53 % of its pressure within 2e-3 s of being left alone (stop 89), and every modulus or path read
// from it would be its collapse.
void require_equilibrium(const DemCell& prepared, const Material& material, const PreparationSpec& spec) {
  const double hold = equilibrium_hold_seconds(material, spec);
  const double drift = pressure_drift_at_rest(prepared, hold, spec.q_t, spec.pressure);
  if (drift <= spec.equilibrium_drift) return;
  std::ostringstream msg;
  msg << "preparation: the packing is not in equilibrium: left alone at fixed volume without damping for " << hold
      << " s (preparation.equilibrium_hold = " << spec.equilibrium_hold << " inertial times), its pressure moved by "
      << 100 * drift << " % of p_0 = " << spec.pressure << " Pa (preparation.equilibrium_drift: expected at most "
      << 100 * spec.equilibrium_drift
      << " %): the preparation's damping and servo held it up. Prepare it denser (a lower preparation.compression_friction) "
         "or at a higher preparation.pressure, or another preparation.seed.";
  throw std::runtime_error(msg.str());
}

}  // namespace

double equilibrium_hold_seconds(const Material& material, const PreparationSpec& spec) {
  return spec.equilibrium_hold * mean_diameter(spec) * std::sqrt(material.density / spec.pressure);
}

double pressure_drift_at_rest(const DemCell& cell, double duration, double q_t, double p_ref) {
  DemCell held(cell.state(), cell.material(), cell.skin());
  const double p_start = pressure_of(held.measures().stress);
  const double dt = held.time_step(q_t);
  const MixedControl fixed_volume;  // nothing stress-controlled, L = 0; measures at every step
  double drift = 0;
  for (double t = 0; t < duration; t += dt) {
    held.step_mixed(fixed_volume, dt);
    const double p = pressure_of(held.stress());
    if (!std::isfinite(p)) return std::numeric_limits<double>::infinity();
    drift = std::max(drift, std::abs(p - p_start));
  }
  return drift / p_ref;
}

DemCell random_gas(const Material& material, const PreparationSpec& spec) {
  check(spec, material);
  SeededRandom rng(spec.seed);
  std::vector<double> radius(spec.spheres);
  double solid_volume = 0;
  for (double& r : radius) {
    r = 0.5 * rng.uniform(spec.min_diameter, spec.max_diameter);
    solid_volume += 4.0 / 3.0 * std::numbers::pi * r * r * r;
  }
  const double side = std::cbrt(solid_volume / spec.initial_solid_fraction);
  // Random sequential addition in a cube, largest spheres first so the gas always fits.
  std::vector<std::size_t> order(radius.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return radius[a] > radius[b]; });
  std::vector<Vec3> position(radius.size());
  std::vector<std::size_t> placed;
  constexpr int kTries = 100000;
  for (std::size_t p : order) {
    bool ok = false;
    for (int attempt = 0; attempt < kTries && !ok; ++attempt) {
      const Vec3 x(rng.uniform() * side, rng.uniform() * side, rng.uniform() * side);
      ok = true;
      for (std::size_t q : placed) {
        Vec3 d = x - position[q];
        for (int a = 0; a < 3; ++a) d[a] -= side * std::round(d[a] / side);
        const double touch = radius[p] + radius[q];
        if (d.squaredNorm() < touch * touch) { ok = false; break; }
      }
      if (ok) position[p] = x;
    }
    if (!ok)
      throw std::runtime_error("preparation: could not place the random gas; lower preparation.initial_solid_fraction");
    placed.push_back(p);
  }
  return DemCell::from_packing(side * Mat3::Identity(), position, radius, material, spec.skin * mean_diameter(spec));
}

DemCell prepare_cell(const Material& material, const PreparationSpec& spec, PreparationReport* report,
                     const PreparationObserver& observer) {
  check(material);
  DemCell cell = random_gas(material, spec);
  cell.set_local_damping(spec.local_damping);
  cell.set_friction(spec.compression_friction);
  PreparationReport r;
  r.compression_steps = settle_at_pressure(cell, material, spec, "compression", observer);
  cell.set_friction(material.contact.friction);
  if (material.effects.bonds) r.bonds = cell.create_bonds(material.bond.bonding_distance);
  r.relaxation_steps = settle_at_pressure(cell, material, spec, "relaxation", observer);

  // The template starts at rest in time and strain: t = 0, F = I, no preparation damping.
  CellState st = cell.state();
  st.time = 0;
  st.h_reference = st.h;
  DemCell prepared(std::move(st), material, cell.skin());
  r.final = prepared.measures();
  require_equilibrium(prepared, material, spec);
  if (report) *report = r;
  return prepared;
}

}  // namespace grainbank::dem
