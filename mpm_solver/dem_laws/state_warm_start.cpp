#include "mpm_solver/dem_laws/state_warm_start.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

#include "dem_sampler/cell/substepping.hpp"
#include "database/surrogate/state_features.hpp"

namespace grainbank::mpm {

StateWarmStart::StateWarmStart(std::vector<StateSnapshot> snapshots, const surrogate::FeatureConstants& constants,
                               const surrogate::LengthScales& scales, const StateWarmStartSettings& settings)
    : snapshots_(std::move(snapshots)), constants_(constants), scales_(scales), settings_(settings) {
  if (snapshots_.empty()) throw std::invalid_argument("state warm start: no snapshot to start from");
  if (std::none_of(snapshots_.begin(), snapshots_.end(), [](const StateSnapshot& s) { return s.state.damage == 0; }))
    throw std::invalid_argument("state warm start: no undamaged snapshot (the template) to start an undamaged point from");
  if (!(settings_.stress_tolerance > 0))
    throw std::invalid_argument("fallback.stress_tolerance: expected a positive stress [Pa]");
  if (!(settings_.servo_inertial_number > 0))
    throw std::invalid_argument("fallback.servo_inertial_number: expected a positive number");
  if (settings_.catch_up_steps < 1) throw std::invalid_argument("fallback.catch_up_steps: expected at least 1");
  if (settings_.catch_up_legs < 1) throw std::invalid_argument("fallback.catch_up_legs: expected at least 1");
  if (!(settings_.catch_up_strain_per_step >= 0))
    throw std::invalid_argument("fallback.catch_up_strain_per_step: expected a strain ≥ 0 (0: no limit)");
  if (settings_.max_servo_steps < 1) throw std::invalid_argument("fallback.max_servo_steps: expected at least 1");
  surrogate::check(constants_);
  keys_.reserve(snapshots_.size());
  for (const StateSnapshot& s : snapshots_) keys_.push_back(key(s.state));
}

StateWarmStart::StateKey StateWarmStart::key(const surrogate::PointState& state) const {
  const surrogate::FeatureVector f =
      surrogate::feature_vector(surrogate::state_features(state, dem::Mat3::Zero(), constants_));
  StateKey k;
  for (std::size_t i = 0; i < kStateFeatures; ++i) k[i] = f[i] / scales_[i];
  return k;
}

double StateWarmStart::distance(const StateKey& a, const StateKey& b) {
  double d = 0;
  for (std::size_t j = 0; j < kStateFeatures; ++j) d += (a[j] - b[j]) * (a[j] - b[j]);
  return d;
}

bool StateWarmStart::not_more_damaged(const surrogate::PointState& cell, std::int64_t bonds,
                                      const surrogate::PointState& point) {
  const double one_bond = bonds > 0 ? 1.0 / static_cast<double>(bonds) : 0.0;
  return cell.damage <= point.damage + one_bond;
}

std::size_t StateWarmStart::nearest(const surrogate::PointState& state) const {
  const StateKey q = key(state);
  std::size_t best = 0;
  double best_distance = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < keys_.size(); ++i) {
    if (!not_more_damaged(snapshots_[i].state, snapshots_[i].cell.initial_bond_count, state)) continue;
    const double d = distance(keys_[i], q);
    if (d < best_distance) {
      best_distance = d;
      best = i;
    }
  }
  return best;
}

WarmStartOutcome StateWarmStart::start(const surrogate::PointState& state, const LiveCellModel& model,
                                       std::optional<OwnCell> own) const {
  // The point's own cell whenever it has one: the state key's distance does not tell how far a
  // foreign packing is from the point's (a snapshot nearer in key than the own cell needed 7× its
  // servo steps, stop 46).
  if (own) {
    WarmStartOutcome outcome{std::move(own->cell), 0, true, {}, {}};
    catch_up(outcome.cell, own->motion, model, outcome.catch_up);
    return outcome;
  }
  const std::size_t index = nearest(state);
  dem::DemCell cell = model.cell_from(snapshots_[index].cell);
  const dem::StressServoResult result = servo(cell, state, model);
  return {std::move(cell), index, false, result, {}};
}

void StateWarmStart::catch_up(dem::DemCell& cell, std::span<const KinematicIncrement> motion,
                              const LiveCellModel& model, CouplingCounters& counters) const {
  double elapsed = 0, strain_path = 0;
  for (const KinematicIncrement& increment : motion) {
    elapsed += increment.dt;
    strain_path += increment.strain().norm();
  }
  if (!(elapsed > 0)) return;
  const dem::Substepping& q = model.settings().substepping;
  const double dt = cell.time_step(q.q_t);
  const std::size_t legs = std::min(motion.size(), static_cast<std::size_t>(settings_.catch_up_legs));
  double steps = static_cast<double>(settings_.catch_up_steps);
  if (settings_.catch_up_strain_per_step > 0) steps = std::max(steps, strain_path / settings_.catch_up_strain_per_step);
  const double speed_up = std::max(1.0, elapsed / (steps * dt));
  const auto drive = [&](const KinematicIncrement& increment) {
    model.advance(cell, increment, counters);
    counters.warm_start_catch_up_steps += static_cast<std::uint64_t>(dem::substep_count(increment.dt, dt, q.q_n));
  };
  std::size_t begin = 0;
  for (std::size_t leg = 1; leg <= legs; ++leg) {
    const std::span<const KinematicIncrement> part = motion.subspan(begin, motion.size() * leg / legs - begin);
    begin += part.size();
    Mat2 F = Mat2::Identity();
    double duration = 0;
    for (const KinematicIncrement& increment : part) {
      F = increment.F * F;
      duration += increment.dt;
    }
    if (!(duration > 0)) continue;
    KinematicIncrement whole;
    try {
      whole = KinematicIncrement::of_deformation(F, duration / speed_up);
    } catch (const std::invalid_argument&) {  // turned by π: no single drive does it
      for (const KinematicIncrement& increment : part) drive(increment);
      continue;
    }
    drive(whole);
  }
}

dem::StressServoResult StateWarmStart::servo(dem::DemCell& cell, const surrogate::PointState& target,
                                             const LiveCellModel& model) const {
  // Quasi-static: the servo moves the cell at inertial number I at the target's pressure, and an
  // error of that pressure drives it at full rate.
  const double pressure = surrogate::effective_pressure(target.stress, constants_);
  dem::StressServoSettings servo;
  servo.tolerance = settings_.stress_tolerance;
  servo.stress_scale = pressure;
  servo.max_rate = settings_.servo_inertial_number * std::sqrt(pressure / constants_.density) / constants_.diameter;
  servo.dt = cell.time_step(model.settings().substepping.q_t);
  servo.max_steps = settings_.max_servo_steps;
  // The MPM sees the symmetric part of a cell's stress (plane_stress_of); so does the servo.
  return dem::servo_to_stress(cell, 0.5 * (target.stress + target.stress.transpose()), servo);
}

}  // namespace grainbank::mpm
