// The state-keyed surrogate law (issue 13): every point carries its own state (σ, φ, Z, D) and
// integrates it with the rate answers of a surrogate index over a cell library
// (database/surrogate), falling back to a live DEM cell where the surrogate's own error estimate is
// too large.
//
// Promises:
// - Each update of a point that is not live takes surrogate_step for its state under the
//   increment's L: when the estimated error of the step's stress [Pa] is within `tolerance` the
//   point's state advances with the predicted answer (source hit); otherwise the point goes live.
// - A step that would spend past the error budget (the estimated errors the point has summed since
//   its last live spell or re-anchoring) is not taken as it is. With warm_start "state" the point is
//   re-anchored: a cell is started as for a live spell (below: the point's own former cell, or the
//   template, caught up on the point's motion), the point takes that cell's state (σ, φ, Z and D;
//   from a servoed snapshot, its D only when higher than the point's: bonds do not heal) and keeps
//   the cell for its next start, and the step is asked again from that state. No live step is run:
//   the drift the budget guards against is a state no cell carries (stop 40: a column that stood
//   because its points drifted to a strength no cell has), and the cell, driven through the point's
//   motion, has not drifted. Only a step whose own estimated error exceeds the whole budget (possible
//   only with a tolerance above the budget) is run live on that cell, a spell of the budget. With
//   warm_start "replay" the point goes live instead, and the replay ends the drift exactly. Either
//   way the errors summed between a point's cells never exceed the budget.
// - A replay starts from the point's checkpoint: the cell of its last live spell that was itself
//   started by replay, kept when the point returned, with the increments since then. It is the cell
//   a replay from the template would give, to the bit, and each increment is replayed at most once.
// - Going live with warm_start "state" (the default): the point's cell is its own former cell, or,
//   for a point without one, the template (every point starts in its state), caught up on the
//   point's motion since (state_warm_start.hpp), so its cost does not grow with the run; with
//   first_cell "snapshot", the stored cell nearest in state (the library's snapshots of the
//   template's paths, and the template itself), brought to the point's stress by the stress servo.
//   The point then carries the cell's state, σ, φ, Z and D; a servo that does not converge leaves
//   the stress the packing could reach (or, with unconverged "replay", the point replays). With
//   warm_start "replay", and on the point's first step, the cell is rebuilt by replaying the
//   point's own increments (exact: the cell a live-law point would own). A live cell
//   answers as in the live law (LiveCellModel). With tolerance 0 every step with stretching is live and
//   starts from the template, so the law equals the live law to round-off.
// - Every live step's response enters the index as a new sample at the end of its step (end_step,
//   issue 13, item 4), so the next step's queries near it may hit: the cell's state `sample_span`
//   steps before (or at the start of the spell, if that is nearer) and now, under the mean L of
//   those steps over their duration, as the library's samples span up to `sample_span` recorded
//   intervals (reindex.hpp, which says why). Its origin is path −(slot + 1), record = the index of
//   the increment in the point's history. The step's samples enter in slot order: a run is the same
//   on any number of threads.
// - A live point returns to the surrogate, with the cell's σ, φ, Z and D, after `return_after`
//   consecutive live steps whose surrogate estimate (asked before the step's sample is inserted)
//   was within the tolerance (0: it stays live); after one such step when the spell was started by
//   the spent budget (by replay: the surrogate could answer it). It keeps that cell: its next state
//   warm start begins from it unless the cell has more broken bonds than the point
//   (state_warm_start.hpp).
// - A point's volume follows its own F (V = V₀ det F) whether it is live or not: a cell warm-started
//   by state has another volume history than the point's.
// - The P-wave modulus of a surrogate point is LiveCellModel::modulus at the point's φ and Z.
// - start_report() gives the length-scale fit (its seed, probes, losses, and each scale with its
//   evidence, length_scales.hpp) and, when the probes leave scales undetermined, a note naming them:
//   the fit is a draw along those, and other fit_seed values show what that draw moves.
// - finish() measures the error estimate where the run went live: the library alone (its dataset,
//   without what the run learned) predicts at most kAuditedStates of the samples the live cells
//   learned, at the run's length scales (estimate_audit.hpp). end_report() gives it (samples,
//   coverage, medians of error/estimate, of the error and of the estimate), and a note when the
//   estimate covered less than half of those errors. It also gives where those samples lay against
//   the library's, feature by feature (library_reach.hpp, beyond all but kReachTail of the library's
//   samples at either end), and a note naming the features in which a share kReachNoted or more of
//   them lay beyond. Both read only what a restart keeps, so a resumed run reports the same.
// - save_state/restore_state keep each point's state, live flag, steps inside, replay history,
//   cell, kept cell, checkpoint and the steps a learned sample spans, and the samples learned so far:
//   a restart continues bit for bit. It also keeps the constants and the sample span those samples
//   were made with, and a law keyed otherwise (another library, pressure_floor or sample_span)
//   refuses to restore them.
#pragma once
#include <atomic>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include "mpm_solver/core/constitutive_law.hpp"
#include "mpm_solver/core/dem_backed_law.hpp"
#include "mpm_solver/dem_laws/live_cell_model.hpp"
#include "mpm_solver/dem_laws/state_warm_start.hpp"
#include "database/surrogate/estimate_audit.hpp"
#include "database/surrogate/length_scales.hpp"
#include "database/surrogate/library_reach.hpp"
#include "database/surrogate/reindex.hpp"
#include "database/surrogate/surrogate_index.hpp"
#include "database/surrogate/surrogate_step.hpp"

namespace grainbank::mpm {

struct SurrogateLawSettings {
  double tolerance = 0;  // [Pa] estimated error of one step's stress above which a point goes live
  surrogate::SurrogateOptions surrogate;  // k (and the local fit's ridge)
  surrogate::LengthScaleSearch fit;       // of the length scales on the dataset (its seed)
  int return_after = 0;   // live steps within the tolerance before a point returns to the surrogate
  // [Pa] the sum of a point's estimated step errors since its last live spell or re-anchoring may
  // not exceed this: a step that would exceed it re-anchors the point (or goes live, by replay)
  // first (issue 13: an error budget per point over the run, so small errors cannot drift
  // unchecked). Infinite: no budget.
  double error_budget = std::numeric_limits<double>::infinity();
  // Steps (and recorded intervals of the library) one sample's rate spans, ≥ 1 (reindex.hpp).
  std::size_t sample_span = 1;
  LiveDemSettings live;   // of the live cells
  enum class WarmStart { state, replay } warm_start = WarmStart::state;
  // Of the state warm start; a stress_tolerance of 0 means `tolerance` (and with both 0, replay).
  StateWarmStartSettings state_warm_start;
};

class SurrogateLaw : public ConstitutiveLaw, public DemBackedLaw {
 public:
  // Fits the length scales on `dataset` (leave-path-out, length_scales.hpp) and indexes it; an
  // empty dataset gives unit scales and an index that starts empty (every point goes live and the
  // index learns from the cells). `snapshots` are the stored cells a state warm start may begin
  // from, besides the template. Throws std::invalid_argument on bad settings.
  SurrogateLaw(const dem::DemCell& cell_template, surrogate::Dataset dataset, SurrogateLawSettings settings,
               std::vector<StateSnapshot> snapshots = {});

  std::string name() const override { return "surrogate"; }
  double density() const override { return model_.density(); }
  std::size_t add_point(PointStress& initial_stress) override;
  void update(std::size_t slot, const KinematicIncrement& increment, const Mat2& F, PointStress& stress) override;
  double p_wave_modulus(std::size_t slot) const override;
  double time_step_limit(std::size_t slot, const Mat2& F, const Mat2& L) const override;
  double damage(std::size_t slot) const override { return points_[slot].state.damage; }
  bool expensive() const override { return live_points_ > 0; }
  void save_state(LawStateWriter& out) const override;
  void restore_state(LawStateReader& in) override;
  const DemBackedLaw* dem_backed() const override { return this; }
  LawReport start_report() const override;
  void finish() override;
  LawReport end_report() const override;
  static constexpr std::size_t kAuditedStates = 10000;
  // The library's share left out at either end of each feature, and the share of live states beyond
  // one end that the end report notes.
  static constexpr double kReachTail = 0.01, kReachNoted = 0.25;

  StressSource source(std::size_t slot) const override { return points_[slot].source; }
  double estimated_error(std::size_t slot) const override { return points_[slot].error; }
  CouplingCounters point_counters(std::size_t slot) const override { return points_[slot].counters; }
  const dem::DemCell* live_cell(std::size_t slot) const override { return points_[slot].cell.get(); }

  const surrogate::SurrogateIndex& index() const { return *index_; }
  // The fit of the length scales (none on a dataset of fewer than two samples: unit scales).
  const std::optional<surrogate::LengthScaleFit>& length_scale_fit() const { return fit_; }
  // None when live cells start by replay.
  const StateWarmStart* state_warm_start() const { return warm_start_ ? &*warm_start_ : nullptr; }
  const surrogate::PointState& state(std::size_t slot) const { return points_[slot].state; }
  // Samples inserted from live responses so far.
  std::size_t learned() const;
  const std::vector<surrogate::Sample>& learned_samples() const { return learned_; }
  // Inserts the samples the step's live points learned, in slot order.
  void end_step() override;

 private:
  struct Point {
    surrogate::PointState state;
    double error = 0;
    StressSource source = StressSource::hit;
    std::unique_ptr<dem::DemCell> cell;       // live only
    // The cell the point handed back when it last returned to the surrogate or was re-anchored, and
    // how many increments of its history that cell has seen: its next start catches it up on the
    // rest (state_warm_start.hpp).
    std::unique_ptr<dem::DemCell> parked;
    std::size_t parked_at = 0;
    // The point's last exact cell (the cell a live-law point would own after the first
    // `checkpoint_at` increments of its history): a replay starts from it instead of the template.
    std::unique_ptr<dem::DemCell> checkpoint;
    std::size_t checkpoint_at = 0;
    bool cell_is_exact = false;               // the live cell was started by replay
    bool budget_spell = false;                // the live spell was started by the spent budget
    int steps_inside = 0;                     // consecutive live steps within the tolerance
    double spent = 0;  // [Pa] estimated errors summed since the last live spell or re-anchoring
    std::vector<KinematicIncrement> history;  // every increment so far, for the replay
    std::vector<std::size_t> neighbours;      // of the point's last surrogate step: its next query's hint
    std::vector<surrogate::Sample> learned_this_step;  // inserted by end_step
    // The live cell's last `sample_span` steps: the state before each, its L and dt.
    struct SpanStep {
      surrogate::PointState before;
      dem::Mat3 L;
      double dt = 0;
    };
    std::vector<SpanStep> span;
    CouplingCounters counters;
  };

  // A cell for the point (state warm start, or replay), whose state the point takes. True when it is
  // the point's own cell, caught up on the point's motion.
  bool start_cell(Point& p);
  // The surrogate's step from the point's state, its last neighbours as the search's hint.
  surrogate::SurrogateStep answer(Point& p, const dem::Mat3& L, double dt) const;
  void go_live(Point& p);
  void reanchor(Point& p);
  // The point gives its live cell up, keeping it for its next start (and as a checkpoint when exact);
  // the cell has seen the first `seen` increments of the point's history.
  void park(Point& p, std::size_t seen);
  void advance_live(std::size_t slot, Point& p, const KinematicIncrement& increment, const dem::Mat3& L,
                    PointStress& stress);
  // The sample of the point's span: its first state to now, under the span's mean L.
  void learn_span(std::size_t slot, Point& p);
  void learn(const std::vector<surrogate::Sample>& samples);

  SurrogateLawSettings settings_;
  LiveCellModel model_;
  surrogate::PointState template_state_;
  std::optional<surrogate::LengthScaleFit> fit_;
  std::vector<surrogate::Sample> library_;  // the dataset's samples, for the audit at the end
  // What finish() measured where the run went live: the library's estimate there, and its reach.
  struct LiveStateMeasures {
    surrogate::EstimateCalibration estimate;
    surrogate::LibraryReach reach;
  };
  std::optional<LiveStateMeasures> live_states_;  // set by finish()
  std::unique_ptr<surrogate::SurrogateIndex> index_;
  std::optional<StateWarmStart> warm_start_;
  // Appended only by end_step and restore_state, which run outside any parallel region.
  std::vector<surrogate::Sample> learned_;
  std::vector<Point> points_;
  std::atomic<long> live_points_{0};
};

}  // namespace grainbank::mpm
