#include "dem_sampler/cell/regeneration.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "dem_sampler/cell/periodic_cell.hpp"

namespace grainbank::dem {
namespace {

Mat3 symmetric_part(const Mat3& m) { return 0.5 * (m + m.transpose()); }

void check(const RegenerationSettings& s, const Material& material) {
  auto fail = [](const char* what) { throw std::invalid_argument(std::string("regeneration: ") + what); };
  if (!(s.tolerance_fraction > 0 && s.tolerance_fraction < 1)) fail("tolerance_fraction: expected a number in (0, 1)");
  if (!(s.scale_floor > 0 && s.scale_floor <= 1)) fail("scale_floor: expected a number in (0, 1]");
  if (!(s.inertial_number > 0) || !std::isfinite(s.inertial_number)) fail("inertial_number: expected a positive number");
  if (s.max_servo_steps < 1) fail("max_servo_steps: expected at least 1");
  require_stable_time_step_factor(s.q_t, material.contact.restitution, "regeneration: q_t");
}

}  // namespace

std::int64_t break_most_tensile_bonds(CellState& state, const Mat3& stress, std::int64_t keep) {
  std::vector<std::size_t> intact;
  std::vector<double> traction(state.bonds.size(), 0.0);
  for (std::size_t k = 0; k < state.bonds.size(); ++k) {
    if (!state.bonds[k].intact()) continue;
    const Pair& p = state.pairs[k];
    const Vec3 branch =
        state.h * (state.reduced_position[p.j] + shift_vector(static_cast<int>(p.image)).cast<double>() -
                   state.reduced_position[p.i]);
    const Vec3 n = branch.normalized();
    traction[k] = n.dot(stress * n);
    intact.push_back(k);
  }
  const std::int64_t to_break = std::max<std::int64_t>(0, static_cast<std::int64_t>(intact.size()) - keep);
  std::stable_sort(intact.begin(), intact.end(), [&](std::size_t a, std::size_t b) { return traction[a] > traction[b]; });
  for (std::int64_t k = 0; k < to_break; ++k) state.bonds[intact[static_cast<std::size_t>(k)]].integrity = 0;
  return to_break;
}

Regeneration regenerate(const DemCell& worn, CellState fresh, const RegenerationSettings& settings) {
  check(settings, worn.material());
  const Mat3 target = symmetric_part(worn.stress());
  const double damage = worn.measures().damage;
  const auto keep = static_cast<std::int64_t>(std::llround((1 - damage) * static_cast<double>(fresh.initial_bond_count)));
  const std::int64_t broken = break_most_tensile_bonds(fresh, target, keep);
  fresh.time = worn.time();
  DemCell cell(std::move(fresh), worn.material(), worn.skin());

  StressServoResult servo;
  const double scale = std::max(target.cwiseAbs().maxCoeff(),
                                settings.scale_floor * symmetric_part(cell.stress()).cwiseAbs().maxCoeff());
  if (scale > 0) {
    const std::vector<double>& r = cell.radii();
    const double diameter = 2 * std::accumulate(r.begin(), r.end(), 0.0) / static_cast<double>(r.size());
    StressServoSettings s;
    s.tolerance = settings.tolerance_fraction * scale;
    s.stress_scale = scale;
    s.max_rate = settings.inertial_number * std::sqrt(scale / cell.material().density) / diameter;
    s.dt = cell.time_step(settings.q_t);
    s.max_steps = settings.max_servo_steps;
    servo = servo_to_stress(cell, target, s);
  } else {
    servo.converged = true;  // both cells are free of stress: nothing to servo
  }

  CellState state = cell.state();
  state.h_reference = worn.deformation_gradient().inverse() * state.h;
  return {DemCell(std::move(state), worn.material(), worn.skin()), broken, servo};
}

}  // namespace grainbank::dem
