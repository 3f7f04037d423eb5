// A live fallback that starts in the right state (issue 13, item 3): when a surrogate point goes
// live or is re-anchored, its cell is not rebuilt by replaying the point's whole history at its own
// pace (a cost that grows with the run). A point that has had a cell takes it again, caught up on
// the point's motion since; a point that has not takes the template, caught up on its whole motion
// (first_cell "template", the default), or a copy of the stored cell whose state is nearest to its
// own, brought to its stress by the engine's stress servo (first_cell "snapshot";
// dem_sampler/cell/stress_servo.hpp).
//
// Promises:
// - nearest() compares states on the state part of the surrogate's key: ln(p/p_ref), η cos 3θ, η
//   sin 3θ, φ, Z and D (state_features.hpp), each difference divided by the surrogate's length
//   scale of that feature, so "near" means what the surrogate's own fit found to matter. Ties go to
//   the earlier snapshot. Deterministic and safe from any number of threads.
// - It never starts a point from a snapshot with more broken bonds than the point's D (by more than
//   one bond, 1/N_b(0)): bonds do not heal, so such a cell is a weaker material than the point's
//   history made, for good (near D = 0 every other snapshot lies above the point, so without this
//   rule a warm start could only raise its damage). The template (D = 0) always qualifies.
// - start() copies that snapshot and servos it at inertial number servo_inertial_number (at the
//   target's pressure) until its windowed mean stress is within `stress_tolerance` of the point's
//   in every component. The cell keeps the snapshot's φ, Z and D but for the servo's small strain.
// - A point that has had a cell (a live spell or a re-anchoring) starts from it (`own`), however
//   near a snapshot is: the cell carries the point's own fabric and broken bonds, which the state
//   key does not see. That cell is not servoed but caught up: driven along the point's motion
//   since it handed the cell back, sped up uniformly so that it takes catch_up_steps DEM steps
//   (plus at most one per leg, each rounding its steps up; the motion's own pace when it took
//   fewer). The increments are cut into at most catch_up_legs legs of consecutive increments, each
//   driven at the constant velocity gradient of its product F: the cell ends at exactly the point's
//   deformation, and it has gone there by the point's path, not by the straight line to its end
//   (stop 52: a standing column's points, whose motion is the ringing after the gate, came to shear
//   stresses of 50–90 Pa where live cells carry 5–8 Pa when each catch-up took the straight line).
//   The cell then carries the stress, φ, Z and D its packing develops under the point's motion, which
//   the MPM knows exactly, where a servo would bring it to the stress the surrogate integrated,
//   drifted or not: a dense cell servoed at rest carries a flowing point's drifted stress ratio,
//   q/p up to 1.25 (stop 51: one point in steady shear under a held normal stress flowed at
//   1.6–2.1× the live cell's friction when its kept cell was servoed, within 8 % of it when caught
//   up). The catch-up is faster than the point moved (a re-anchoring every ~20 MPM steps of ~100
//   DEM steps each); in fewer steps the cell is left more agitated and more of the points that
//   follow go live (stop 51: at most 50 steps sent 18 % of the demo column's point-steps live, 200
//   steps 12 %). A leg with no principal logarithm (a rotation by π) is replayed increment by
//   increment at its own pace.
// - With catch_up_strain_per_step = ε > 0, a catch-up also takes at least Σ|dε|/ε DEM steps (its
//   motion's strain path, Σ ‖sym L‖ Δt, over ε; never more than the motion's own pace): a long
//   motion is not driven faster than ε per DEM step. Why: bonds break in a fast drive that the same
//   motion at its own pace leaves intact (stop 57). With samples of one record it keeps a flowing
//   column's damage and stress field near live's over 0.3 s, at about a third more CPU
//   (docs/surrogate.md, "Stop 69").
// - A point without a cell of its own starts, with first_cell "template", from the template caught
//   up on the point's whole motion (every point starts in the template's state), as if the template
//   had been its own cell from the start: no servo, and no stress the surrogate integrated enters
//   the cell (stop 52: a snapshot servoed to the point's stress kept the servo's residual, up to
//   stress_tolerance, for as long as its point stood). With first_cell "snapshot" it starts from the
//   nearest snapshot, servoed.
// - A servo that does not converge (max_servo_steps, or no progress: the point's stress lies beyond
//   what the packing can carry, e.g. a surrogate state that drifted past the yield surface) leaves
//   the cell at the nearest stress it could reach; the outcome says so, and the caller keeps that
//   cell or replays the point's history instead (`replay_unconverged`).
#pragma once
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "dem_sampler/cell/stress_servo.hpp"
#include "mpm_solver/dem_laws/live_cell_model.hpp"
#include "database/surrogate/surrogate_index.hpp"

namespace grainbank::mpm {

// A stored cell and the state it carries (σ, φ, Z, D of the record it was taken after).
struct StateSnapshot {
  surrogate::PointState state;
  dem::CellState cell;
};

struct StateWarmStartSettings {
  double stress_tolerance = 0;         // [Pa] > 0, per stress component
  double servo_inertial_number = 1e-3; // servo rate |L| ≤ I √(p/ρ) / d: quasi-static
  long max_servo_steps = 20000;        // DEM steps
  bool replay_unconverged = false;     // an unconverged servo: replay the point's history instead
  long catch_up_steps = 200;            // DEM steps of a catch-up at most (above)
  long catch_up_legs = 40;              // legs of a catch-up's path at most (above)
  double catch_up_strain_per_step = 0;  // > 0: a catch-up's strain per DEM step at most (above); 0: no limit
  // A point's first cell: the template caught up on its motion, or the nearest snapshot, servoed.
  enum class FirstCell { template_caught_up, nearest_snapshot };
  FirstCell first_cell = FirstCell::template_caught_up;
};

struct WarmStartOutcome {
  dem::DemCell cell;         // where the servo or the catch-up left it
  std::size_t snapshot = 0;  // index of the snapshot it started from (when not from its own cell)
  bool own = false;          // started from the point's own former cell, caught up
  dem::StressServoResult servo;  // of a snapshot
  // Of the point's own cell: its DEM steps (warm_start_catch_up_steps) and re-tilings.
  CouplingCounters catch_up;
};

// A point's own former cell (handed over: the start continues it) and the point's increments since
// it handed the cell back.
struct OwnCell {
  dem::DemCell cell;
  std::span<const KinematicIncrement> motion;
};

class StateWarmStart {
 public:
  // Throws std::invalid_argument on an empty snapshot list, one without an undamaged snapshot, or bad
  // settings.
  StateWarmStart(std::vector<StateSnapshot> snapshots, const surrogate::FeatureConstants& constants,
                 const surrogate::LengthScales& scales, const StateWarmStartSettings& settings);

  const StateWarmStartSettings& settings() const { return settings_; }
  std::size_t size() const { return snapshots_.size(); }
  const StateSnapshot& snapshot(std::size_t i) const { return snapshots_[i]; }
  std::size_t nearest(const surrogate::PointState& state) const;
  WarmStartOutcome start(const surrogate::PointState& state, const LiveCellModel& model,
                         std::optional<OwnCell> own = std::nullopt) const;

 private:
  static constexpr std::size_t kStateFeatures = 6;  // the leading, loading-free entries of the key
  using StateKey = std::array<double, kStateFeatures>;
  StateKey key(const surrogate::PointState& state) const;
  static double distance(const StateKey& a, const StateKey& b);
  // Whether a cell in state `cell` with `bonds` initial bonds may start a point in state `point`.
  static bool not_more_damaged(const surrogate::PointState& cell, std::int64_t bonds, const surrogate::PointState& point);
  dem::StressServoResult servo(dem::DemCell& cell, const surrogate::PointState& target, const LiveCellModel& model) const;
  void catch_up(dem::DemCell& cell, std::span<const KinematicIncrement> motion, const LiveCellModel& model,
                CouplingCounters& counters) const;

  std::vector<StateSnapshot> snapshots_;
  std::vector<StateKey> keys_;
  surrogate::FeatureConstants constants_;
  surrogate::LengthScales scales_;
  StateWarmStartSettings settings_;
};

}  // namespace grainbank::mpm
