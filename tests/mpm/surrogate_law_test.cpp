// The surrogate law (issue 13) on a small real library sampled in-process (forty generated
// two-segment paths of the 64-sphere cohesive cell, tests/database/surrogate_test_util.hpp):
// - a point driven along each stored path's own velocity gradients follows that path's stress
//   within the error the law estimates, summed over the steps;
// - with tolerance 0 every step is live and the law is the live law;
// - live responses learned by one point let a second point along the same motion hit more;
// - a point goes live from the stored cell nearest in state, servoed to its stress: no replay, and
//   no jump of stress beyond the servo's tolerance and the step's own elastic increment;
// - a point with a cell of its own starts from it, caught up on the point's motion since it was kept;
// - a restart continues bit for bit; a scene names the law and its keys are checked.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "tests/database/surrogate_test_util.hpp"
#include "common/json_input.hpp"
#include "mpm_solver/core/solver.hpp"
#include "mpm_solver/dem_laws/library_link.hpp"
#include "mpm_solver/dem_laws/live_dem_law.hpp"
#include "mpm_solver/dem_laws/surrogate_law.hpp"
#include "mpm_solver/io/restart.hpp"
#include "mpm_solver/io/scene_input.hpp"
#include "database/store/library.hpp"
#include "database/surrogate/surrogate_step.hpp"

namespace grainbank::mpm {
namespace {

constexpr double kDt = 2e-4;  // the library's record interval
constexpr double kNoLimit = std::numeric_limits<double>::infinity();

// The library, its template and its dataset, built once for the whole process.
struct SharedLibrary {
  surrogate::test::TempDir dir{"grainbank-surrogate-law"};
  std::filesystem::path path = dir.path() / "LIB";
  std::int64_t template_id = 0;
  std::optional<dem::DemCell> cell;
  surrogate::Dataset dataset;
  std::vector<std::vector<db::Record>> paths;
  std::vector<StateSnapshot> snapshots;
};

const SharedLibrary& shared() {
  static const SharedLibrary* const library = [] {
    auto* s = new SharedLibrary;
    db::Library library = surrogate::test::build_library(s->dir, s->path, surrogate::test::kGeneralPaths);
    s->template_id = library.catalogue().templates().front().id;
    s->cell.emplace(library.restore(library.template_cell(s->template_id)));
    s->dataset = surrogate::reindex(library);
    for (const db::PathRow& path : library.catalogue().paths()) s->paths.push_back(library.records(path.id));
    s->snapshots = LibraryLink(s->path, s->template_id, nullptr).state_snapshots();
    return s;
  }();
  return *library;
}

SurrogateLawSettings settings(double tolerance, int return_after = 0) {
  SurrogateLawSettings s;
  s.tolerance = tolerance;
  s.return_after = return_after;
  return s;
}

std::unique_ptr<SurrogateLaw> surrogate_law(const SurrogateLawSettings& s) {
  return std::make_unique<SurrogateLaw>(*shared().cell, shared().dataset, s, shared().snapshots);
}

// Drives one point of a law through increments at constant L, as the MPM step would.
struct Driver {
  std::size_t slot = 0;
  Mat2 F = Mat2::Identity();
  PointStress stress;
  // The point's update within a step; the step ends when every point of it was updated.
  void update(ConstitutiveLaw& law, const Mat2& L, double dt) {
    const KinematicIncrement increment = KinematicIncrement::of_velocity_gradient(L, dt);
    F = increment.F * F;
    law.update(slot, increment, F, stress);
  }
  // A step of this point alone.
  void operator()(ConstitutiveLaw& law, const Mat2& L, double dt) {
    update(law, L, dt);
    law.end_step();
  }
};

Driver new_point(ConstitutiveLaw& law) {
  Driver d;
  d.slot = law.add_point(d.stress);
  return d;
}

// A motion the library's 0.4 % paths do not cover: 2 % of compression (both in-plane axes) with shear.
std::vector<Mat2> off_library_motion() {
  return std::vector<Mat2>(60, Mat2{{-1.5, 1.0}, {0.0, -0.5}});
}

double stress_distance(const PointStress& a, const PointStress& b) {
  return std::sqrt((a.in_plane - b.in_plane).squaredNorm() + (a.zz - b.zz) * (a.zz - b.zz));
}

TEST(SurrogateLaw, FollowsStoredPathsWithinTheSummedEstimatedError) {
  auto law = surrogate_law(settings(kNoLimit));
  int records = 0, within = 0;
  for (const std::vector<db::Record>& path : shared().paths) {
    Driver d = new_point(*law);
    // The point starts from the template, the path from its first record: the same state.
    double bound = stress_distance(d.stress, plane_stress_of(db::from_stress6(path.front().stress)));
    for (std::size_t k = 0; k + 1 < path.size(); ++k) {
      d(*law, path[k + 1].L.topLeftCorner<2, 2>(), path[k + 1].time - path[k].time);
      ASSERT_EQ(law->source(d.slot), StressSource::hit);
      bound += law->estimated_error(d.slot);
      ++records;
      within += stress_distance(d.stress, plane_stress_of(db::from_stress6(path[k + 1].stress))) <= bound;
    }
  }
  std::printf("%d of %d records within the summed estimated error\n", within, records);
  EXPECT_GT(records, 400);
  // As database.surrogate_integration measures on the same library (98 %): the misses are first
  // steps out of the template at rest, where forty paths leave one state in forty directions.
  EXPECT_GE(within, 0.95 * records);
}

TEST(SurrogateLaw, WithToleranceZeroEveryStepIsLiveAndEqualsTheLiveLaw) {
  auto law = surrogate_law(settings(0));
  LiveDemLaw live(*shared().cell, LiveDemSettings{});
  Driver a = new_point(*law), b = new_point(live);
  EXPECT_EQ(a.stress.in_plane, b.stress.in_plane);
  const std::vector<Mat2> motion = off_library_motion();
  for (int k = 0; k < 8; ++k) {
    a(*law, motion[k], kDt);
    b(live, motion[k], kDt);
    EXPECT_EQ(law->source(a.slot), StressSource::live);
    EXPECT_EQ(a.stress.in_plane, b.stress.in_plane);
    EXPECT_EQ(a.stress.zz, b.stress.zz);
    EXPECT_EQ(law->p_wave_modulus(a.slot), live.p_wave_modulus(b.slot));
    EXPECT_EQ(law->damage(a.slot), live.damage(b.slot));
  }
  const CouplingCounters c = law->point_counters(a.slot);
  EXPECT_EQ(c.went_live, 1u);
  EXPECT_EQ(c.went_live_on_budget, 0u) << "no budget was set";
  EXPECT_EQ(c.live_updates, 8u);
  EXPECT_EQ(c.warm_start_increments, 0u);  // live from the first step: the template itself
  EXPECT_EQ(law->learned(), 8u);
  EXPECT_EQ(law->index().size(), shared().dataset.samples.size() + 8);
}

// The per-step estimated errors of a point along `motion` answered by the surrogate alone.
std::vector<double> surrogate_errors(const std::vector<Mat2>& motion) {
  auto law = surrogate_law(settings(kNoLimit));
  Driver d = new_point(*law);
  std::vector<double> errors;
  for (const Mat2& L : motion) {
    d(*law, L, kDt);
    errors.push_back(law->estimated_error(d.slot));
  }
  return errors;
}

// A tolerance the motion exceeds about halfway.
double median_tolerance(const std::vector<Mat2>& motion) {
  std::vector<double> errors = surrogate_errors(motion);
  std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
  return errors[errors.size() / 2];
}

// Points return to the surrogate after two steps within the tolerance: the second point finds the
// first one's live responses along its way and stays on the surrogate where the first went live.
TEST(SurrogateLaw, LiveResponsesRaiseTheHitRateOfTheNextPoint) {
  const std::vector<Mat2> motion = off_library_motion();
  auto law = surrogate_law(settings(median_tolerance(motion), 2));
  Driver first = new_point(*law), second = new_point(*law);
  for (const Mat2& L : motion) first(*law, L, kDt);
  const CouplingCounters a = law->point_counters(first.slot);
  ASSERT_GE(a.went_live, 1u);
  EXPECT_EQ(law->learned(), a.live_updates);
  for (const Mat2& L : motion) second(*law, L, kDt);
  const CouplingCounters b = law->point_counters(second.slot);
  std::printf("hits along the motion: first point %llu, second point %llu of %zu steps\n",
              static_cast<unsigned long long>(a.hits), static_cast<unsigned long long>(b.hits), motion.size());
  EXPECT_GT(b.hits, a.hits);
  EXPECT_LT(b.live_updates, a.live_updates);
}

// Below p_floor every answer is normalized by p_floor, so only the key can tell a cell in tension
// from one barely compressed. A state in more tension than any sample is off the library and its
// step must say so, or a point keeps a tensile strength no cell has: with ln p clamped at the floor,
// both states below had one key, and on the demo column a point stretched by the gate's release
// held +200 Pa along x, never went live at 50 Pa, and the column ran out a third short.
TEST(SurrogateLaw, TensionBeyondTheLibraryIsAnOffLibraryState) {
  const surrogate::FeatureConstants& constants = shared().dataset.constants;
  double most_tensile = std::numeric_limits<double>::infinity();
  for (const std::vector<db::Record>& path : shared().paths)
    for (const db::Record& record : path)
      most_tensile = std::min(most_tensile, -db::from_stress6(record.stress).trace() / 3);
  const surrogate::PointState template_state = surrogate::point_state(shared().paths.front().front());
  const auto shifted_to = [&](double pressure) {
    surrogate::PointState s = template_state;
    s.stress += (-pressure - s.stress.trace() / 3) * dem::Mat3::Identity();
    return s;
  };
  const surrogate::PointState at_floor = shifted_to(constants.p_floor);
  const surrogate::PointState torn = shifted_to(most_tensile - 10 * constants.p_floor);
  dem::Mat3 stretch = dem::Mat3::Zero();
  stretch(0, 0) = 2;
  auto law = surrogate_law(settings(kNoLimit));
  const surrogate::SurrogateStep near = surrogate::surrogate_step(law->index(), at_floor, stretch, kDt, kNoLimit);
  const surrogate::SurrogateStep far = surrogate::surrogate_step(law->index(), torn, stretch, kDt, kNoLimit);
  std::printf("most tensile sample p = %.0f Pa; estimated error at p_floor %.2f Pa, at p = %.0f Pa %.2f Pa\n",
              most_tensile, near.estimated_error, -torn.stress.trace() / 3, far.estimated_error);
  // One key gives one error to the bit; the library's own samples set how much larger it is (1.4×).
  EXPECT_GT(far.estimated_error, 1.2 * near.estimated_error);
}

// Threads reach a step's points in any order. Points learn from each other's live steps only at the
// end of the step (end_step), so the order does not matter: four points on four turned copies of the
// off-library motion, at a tolerance that sends them live now and then, end bit for bit alike when
// each step updates them in slot order and in reverse. (When each live step entered the index at
// once, a point saw the samples of the points updated before it in the same step.)
TEST(SurrogateLaw, AStepDoesNotDependOnTheOrderItsPointsAreUpdatedIn) {
  const std::vector<Mat2> motion = off_library_motion();
  const double tolerance = 0.5 * median_tolerance(motion);
  const auto run = [&](bool reverse) {
    auto law = surrogate_law(settings(tolerance, 2));
    std::vector<Driver> points;
    std::vector<Mat2> turns;
    for (int i = 0; i < 4; ++i) {
      points.push_back(new_point(*law));
      const double angle = 0.4 * i;
      turns.push_back(Mat2{{std::cos(angle), -std::sin(angle)}, {std::sin(angle), std::cos(angle)}});
    }
    std::vector<PointStress> stresses;
    for (const Mat2& L : motion) {
      for (int j = 0; j < 4; ++j) {
        const int i = reverse ? 3 - j : j;
        points[i].update(*law, turns[i] * L * turns[i].transpose(), kDt);
      }
      law->end_step();
      for (const Driver& d : points) stresses.push_back(d.stress);
    }
    std::uint64_t went_live = 0;
    for (const Driver& d : points) went_live += law->point_counters(d.slot).went_live;
    return std::make_pair(stresses, went_live);
  };
  const auto [forward, went_live] = run(false);
  const auto [backward, went_live_backward] = run(true);
  ASSERT_GE(went_live, 2u) << "the points must learn for the order to matter";
  EXPECT_EQ(went_live_backward, went_live);
  ASSERT_EQ(forward.size(), backward.size());
  for (std::size_t k = 0; k < forward.size(); ++k) {
    EXPECT_EQ(forward[k].in_plane, backward[k].in_plane) << "step " << k / 4 << ", point " << k % 4;
    EXPECT_EQ(forward[k].zz, backward[k].zz) << "step " << k / 4 << ", point " << k % 4;
  }
}

// With no tolerance a point never goes live on its own; with an error budget of a few steps' errors,
// whenever the next step would spend past the budget the point is first brought back to a cell, so
// the estimated errors summed over each run of surrogate steps stay within it. By replay it goes live
// (and returns after one live step): its live stress is exactly the live law's, and each replay
// starts from the cell of the previous one, so no increment goes through a cell twice. By state it is
// re-anchored on a cell without a live step, and nothing is replayed.
TEST(SurrogateLaw, AnErrorBudgetBoundsTheErrorsSpentBetweenLiveSteps) {
  const std::vector<Mat2> motion = off_library_motion();
  const std::vector<double> errors = surrogate_errors(motion);
  const double budget = 5 * median_tolerance(motion);
  double unbounded = 0;
  for (double e : errors) unbounded += e;
  ASSERT_GT(unbounded, 2 * budget) << "the motion must spend past the budget without one";
  for (const auto warm_start : {SurrogateLawSettings::WarmStart::replay, SurrogateLawSettings::WarmStart::state}) {
    const bool by_replay = warm_start == SurrogateLawSettings::WarmStart::replay;
    SCOPED_TRACE(by_replay ? "replay" : "state warm start");
    SurrogateLawSettings s = settings(kNoLimit, 5);
    s.error_budget = budget;
    s.warm_start = warm_start;
    auto law = surrogate_law(s);
    LiveDemLaw live(*shared().cell, LiveDemSettings{});
    Driver d = new_point(*law), truth = new_point(live);
    double spent = 0, largest = 0;
    for (const Mat2& L : motion) {
      const std::uint64_t reanchored = law->point_counters(d.slot).reanchored;
      d(*law, L, kDt);
      truth(live, L, kDt);
      // A re-anchored step starts a new sum with its own error.
      if (law->point_counters(d.slot).reanchored > reanchored) spent = 0;
      spent = law->source(d.slot) == StressSource::hit ? spent + law->estimated_error(d.slot) : 0.0;
      largest = std::max(largest, spent);
      if (by_replay && law->source(d.slot) == StressSource::live) {
        EXPECT_EQ(d.stress.in_plane, truth.stress.in_plane);
      }
    }
    const CouplingCounters& c = law->point_counters(d.slot);
    EXPECT_LE(largest, budget);
    EXPECT_GT(largest, 0.0);
    if (by_replay) {
      EXPECT_GE(c.went_live, 2u);
      EXPECT_EQ(c.went_live_on_budget, c.went_live) << "with no tolerance, only the budget sends a point live";
      // Each spell: the step that went live and one step the surrogate could answer, not return_after.
      EXPECT_LE(c.live_updates, 2 * c.went_live);
      EXPECT_EQ(c.reanchored, 0u);
      EXPECT_GT(c.warm_start_increments, 0u);
      EXPECT_EQ(c.warm_start_servo_steps, 0u);
      EXPECT_LE(c.warm_start_increments + c.live_updates, motion.size()) << "an increment replayed twice";
    } else {
      EXPECT_GE(c.reanchored, 2u);
      EXPECT_EQ(c.went_live, 0u) << "with no tolerance a re-anchored step is answered by the surrogate";
      EXPECT_EQ(c.live_updates, 0u);
      EXPECT_EQ(c.warm_start_increments, 0u);
      // The first re-anchoring catches the template up on the point's whole motion, the later ones
      // the point's own cell on its motion since: nothing is servoed.
      EXPECT_EQ(c.warm_start_servo_steps, 0u);
      EXPECT_GT(c.warm_start_catch_up_steps, 0u);
    }
  }
}

// A law's saved state in memory (law_state_archive.hpp), to be edited between save and restore.
class MemoryArchive : public LawStateWriter, public LawStateReader {
 public:
  void write_table(const std::string& name, const std::vector<double>& rows, std::size_t) override {
    tables[name] = rows;
  }
  void write_cell(const std::string& name, const dem::DemCell& cell) override {
    cells.insert_or_assign(name, cell.state());
  }
  std::vector<double> read_table(const std::string& name, std::size_t) override { return tables.at(name); }
  bool has_table(const std::string& name) override { return tables.count(name) > 0; }
  dem::CellState read_cell(const std::string& name) override { return cells.at(name); }
  std::map<std::string, std::vector<double>> tables;
  std::map<std::string, dem::CellState> cells;
};

// Bonds do not heal. Re-anchored on a servoed snapshot (a point without a cell of its own, with
// first_cell "snapshot"), a point that has integrated more damage than the snapshot keeps its own D.
// Re-anchored on its own kept cell, caught up on its motion, it takes that cell's D: the cell broke
// the bonds the motion breaks, where the point's D is the surrogate's estimate (stop 51). The test
// library's paths break at most two bonds, so the point's later damage is written into its saved
// state (column 12 of "surrogate_points": slot, σ, φ, Z, then D).
TEST(SurrogateLaw, AReanchoredPointKeepsItsDamageUnlessItsOwnCellCaughtUp) {
  std::vector<Mat2> motion(20, off_library_motion().front());
  motion.insert(motion.end(), 40, Mat2{{1.0, 0.0}, {0.0, 1.0}});
  SurrogateLawSettings s = settings(0.5 * median_tolerance(motion), 2);
  auto law = surrogate_law(s);
  Driver d = new_point(*law);
  std::size_t k = 0;
  for (bool was_live = false; k < motion.size(); ++k) {
    d(*law, motion[k], kDt);
    if (law->source(d.slot) == StressSource::live) was_live = true;
    else if (was_live) break;  // back on the surrogate, with a kept cell
  }
  ASSERT_LT(k + 1, motion.size()) << "the point never handed its cell back";
  MemoryArchive archive;
  law->save_state(archive);
  ASSERT_EQ(archive.cells.count("parked_0"), 1u);
  const double kept = LiveCellModel(*shared().cell, LiveDemSettings{}).cell_from(archive.cells.at("parked_0")).measures().damage;
  const double integrated = archive.tables.at("surrogate_points").at(12) + 0.2;
  archive.tables.at("surrogate_points").at(12) = integrated;
  // Every step a hit, and any error spends the budget: the next step re-anchors.
  s.tolerance = kNoLimit;
  s.error_budget = 1e-9;
  for (const bool own : {true, false}) {
    SCOPED_TRACE(own ? "its own cell" : "a snapshot");
    MemoryArchive edited = archive;
    if (!own) {
      edited.cells.erase("parked_0");
      edited.tables.at("surrogate_parked").clear();
      s.state_warm_start.first_cell = StateWarmStartSettings::FirstCell::nearest_snapshot;
    }
    auto resumed = surrogate_law(s);
    Driver e = new_point(*resumed);
    resumed->restore_state(edited);
    ASSERT_DOUBLE_EQ(resumed->damage(e.slot), integrated);
    const std::uint64_t before = resumed->point_counters(e.slot).reanchored;
    e(*resumed, motion[k + 1], kDt);
    ASSERT_EQ(resumed->point_counters(e.slot).reanchored, before + 1);
    if (own) {
      EXPECT_GT(resumed->point_counters(e.slot).warm_start_catch_up_steps, 0u);
      EXPECT_GE(resumed->damage(e.slot), kept);
      EXPECT_LT(resumed->damage(e.slot), integrated);
    } else {
      EXPECT_GT(resumed->point_counters(e.slot).warm_start_servo_steps, 0u);
      EXPECT_GE(resumed->damage(e.slot), integrated);
    }
  }
}

// The state warm start chooses among the library's snapshots and the template: a stored state finds
// its own snapshot, and a state between snapshots gets a cell that carries that state's stress.
TEST(SurrogateLaw, AStateWarmStartFindsTheNearestSnapshotAndServosItToThePointsStress) {
  auto law = surrogate_law(settings(200));
  const StateWarmStart* warm = law->state_warm_start();
  ASSERT_NE(warm, nullptr);
  ASSERT_GT(shared().snapshots.size(), 40u);
  ASSERT_EQ(warm->size(), shared().snapshots.size() + 1) << "the snapshots and the template";
  for (std::size_t i = 0; i < shared().snapshots.size(); i += 7)
    EXPECT_EQ(warm->nearest(shared().snapshots[i].state), i);
  // Records between snapshots of the longest path: states no snapshot holds exactly.
  const auto longest = std::max_element(shared().paths.begin(), shared().paths.end(),
                                        [](const auto& a, const auto& b) { return a.size() < b.size(); });
  int started = 0;
  for (std::size_t k = 3; k < longest->size(); k += 5) {
    const surrogate::PointState target = surrogate::point_state((*longest)[k]);
    const WarmStartOutcome outcome = warm->start(target, LiveCellModel(*shared().cell, LiveDemSettings{}));
    ASSERT_TRUE(outcome.servo.converged) << "record " << k << ": residual " << outcome.servo.residual << " Pa";
    // Held still, the cell carries the target's stress (within twice the servo's tolerance).
    dem::DemCell cell = outcome.cell;
    dem::Mat3 sum = dem::Mat3::Zero();
    constexpr int kSteps = 200;
    for (int step = 0; step < kSteps; ++step) {
      cell.step_with_velocity_gradient(dem::Mat3::Zero(), cell.time_step(0.1));
      sum += 0.5 * (cell.stress() + cell.stress().transpose());
    }
    const dem::Mat3 goal = 0.5 * (target.stress + target.stress.transpose());
    EXPECT_LE((sum / kSteps - goal).cwiseAbs().maxCoeff(), 2 * 200.0) << "record " << k;
    // The cell keeps the state it was copied from, but for the servo's small strain.
    const dem::CellMeasures m = outcome.cell.measures();
    EXPECT_NEAR(m.solid_fraction, warm->snapshot(outcome.snapshot).state.solid_fraction, 0.01);
    ++started;
  }
  EXPECT_GE(started, 2);
}

// Bonds do not heal: a point is never started from a cell that has broken more bonds than its own
// damage says (by more than one bond), however near that cell is in every other respect.
TEST(SurrogateLaw, AStateWarmStartNeverStartsFromAMoreDamagedCell) {
  auto law = surrogate_law(settings(200));
  const StateWarmStart* warm = law->state_warm_start();
  ASSERT_NE(warm, nullptr);
  int damaged = 0;
  for (std::size_t i = 0; i < shared().snapshots.size(); ++i) {
    const surrogate::PointState& stored = shared().snapshots[i].state;
    if (stored.damage == 0) continue;
    ++damaged;
    surrogate::PointState intact = stored;  // the same stress, φ and Z, no bond broken
    intact.damage = 0;
    const std::size_t chosen = warm->nearest(intact);
    const dem::CellState& cell = warm->snapshot(chosen).cell;
    EXPECT_LE(warm->snapshot(chosen).state.damage, 1.0 / static_cast<double>(cell.initial_bond_count))
        << "snapshot " << i;
    // With the point's own damage, the same snapshot is its nearest again.
    EXPECT_EQ(warm->nearest(stored), i);
  }
  EXPECT_GE(damaged, 5) << "the library should hold damaged snapshots to test with";
}

// A point that handed its cell back starts its next spell from that cell, caught up on the point's
// motion since: the cell ends at the kept cell's deformation times that motion (the MPM's kinematics,
// to round-off), in at most catch_up_steps DEM steps (and one more per leg), and with the stress the
// same cell reaches driven at the motion's own pace (the exact replay) within a quarter of the stress
// the motion adds: driven faster, the cell is still quasi-static. With no motion since, the cell is
// the kept one.
TEST(SurrogateLaw, APointThatWasLiveStartsFromItsOwnCellCaughtUpOnItsMotion) {
  auto law = surrogate_law(settings(200));
  const StateWarmStart* warm = law->state_warm_start();
  ASSERT_NE(warm, nullptr);
  const LiveCellModel model(*shared().cell, LiveDemSettings{});
  CouplingCounters counters;
  dem::DemCell kept = model.new_cell();
  const std::vector<Mat2> loading = off_library_motion();
  for (int k = 0; k < 10; ++k) model.advance(kept, KinematicIncrement::of_velocity_gradient(loading[k], kDt), counters);
  const surrogate::PointState state{kept.stress(), 0, 0, 0};  // the own cell is taken whatever the state

  const WarmStartOutcome still = warm->start(state, model, OwnCell{kept, {}});
  EXPECT_TRUE(still.own);
  EXPECT_EQ(still.catch_up.warm_start_catch_up_steps, 0u);
  EXPECT_EQ(still.cell.deformation_gradient(), kept.deformation_gradient());
  EXPECT_EQ(still.cell.stress(), kept.stress());

  const double dem_step = kept.time_step(LiveDemSettings{}.substepping.q_t);
  const std::vector<KinematicIncrement> motion(30, KinematicIncrement::of_velocity_gradient(Mat2{{0.5, 2.0}, {0.0, -0.5}}, kDt));
  ASSERT_GT(30 * kDt, 2 * StateWarmStartSettings{}.catch_up_steps * dem_step) << "the catch-up must be faster than the motion";
  const WarmStartOutcome caught = warm->start(state, model, OwnCell{kept, motion});
  dem::DemCell replayed = kept;
  Mat2 F = Mat2::Identity();
  for (const KinematicIncrement& increment : motion) {
    model.advance(replayed, increment, counters);
    F = increment.F * F;
  }
  EXPECT_TRUE(caught.own);
  const StateWarmStartSettings defaults;
  EXPECT_LE(caught.catch_up.warm_start_catch_up_steps,
            static_cast<std::uint64_t>(defaults.catch_up_steps + defaults.catch_up_legs));
  EXPECT_LT((caught.cell.deformation_gradient() - embed_plane_strain(F) * kept.deformation_gradient()).norm(), 1e-12);
  const auto sym = [](const dem::Mat3& m) { return dem::Mat3(0.5 * (m + m.transpose())); };
  const double added = (sym(replayed.stress()) - sym(kept.stress())).norm();
  const double off = (sym(caught.cell.stress()) - sym(replayed.stress())).norm();
  std::printf("the motion adds %.0f Pa; the catch-up in %llu DEM steps (the motion's pace: %.0f) ends %.0f Pa from the replay\n",
              added, static_cast<unsigned long long>(caught.catch_up.warm_start_catch_up_steps), 30 * kDt / dem_step, off);
  ASSERT_GT(added, 0.0);
  EXPECT_LE(off, 0.25 * added);
}

// A small shear out and back (3e-3, as a standing column rings) ends where it began (the motion's F is
// the identity), but a frictional packing does not: its contacts slip on the way. Caught up leg by
// leg, the kept cell ends near the same cell replayed at the motion's own pace; caught up in one leg,
// the straight line to where the motion ends, it is not moved at all and keeps the stress it had
// (stop 52: a standing column's points so came to 50–90 Pa of shear where live cells carry 5–8 Pa).
// (Not so for a large motion sped up: 3e-2 out and back over 30 increments ends 0.98 kPa from the
// replay in legs, 0.82 kPa in one; docs/surrogate.md, "Stop 52".)
TEST(SurrogateLaw, ACatchUpFollowsTheMotionsPathNotTheStraightLineToItsEnd) {
  auto law = surrogate_law(settings(200));
  const LiveCellModel model(*shared().cell, LiveDemSettings{});
  CouplingCounters counters;
  const dem::DemCell kept = model.new_cell();
  const Mat2 shear{{0.0, 1.0}, {0.0, 0.0}};
  std::vector<KinematicIncrement> motion(15, KinematicIncrement::of_velocity_gradient(shear, kDt));
  motion.insert(motion.end(), 15, KinematicIncrement::of_velocity_gradient(-shear, kDt));
  dem::DemCell replayed = kept;
  for (const KinematicIncrement& increment : motion) model.advance(replayed, increment, counters);
  const auto sym = [](const dem::Mat3& m) { return dem::Mat3(0.5 * (m + m.transpose())); };
  const double left = (sym(replayed.stress()) - sym(kept.stress())).norm();
  const surrogate::PointState state{kept.stress(), 0, 0, 0};
  std::vector<double> off;
  for (const long legs : {StateWarmStartSettings{}.catch_up_legs, 1L}) {
    StateWarmStartSettings one_or_more;
    one_or_more.stress_tolerance = 200;
    one_or_more.catch_up_legs = legs;
    const StateWarmStart warm(shared().snapshots, law->index().constants(), law->index().scales(), one_or_more);
    const WarmStartOutcome caught = warm.start(state, model, OwnCell{kept, motion});
    EXPECT_LT((caught.cell.deformation_gradient() - kept.deformation_gradient()).norm(), 1e-12);
    off.push_back((sym(caught.cell.stress()) - sym(replayed.stress())).norm());
  }
  std::printf("the round trip leaves %.0f Pa; caught up in legs the cell ends %.0f Pa from the replay, in one %.0f\n",
              left, off[0], off[1]);
  ASSERT_GT(left, 0.0);
  EXPECT_LT(off[0], 0.5 * left);
  EXPECT_GT(off[1], 0.5 * left);
}

// Every point starts in the template's state, so a point that has had no cell yet goes live from
// the template caught up on its whole motion (first_cell "template", the default): its cell is at
// the point's deformation to round-off, nothing is servoed and nothing replayed at its own pace.
TEST(SurrogateLaw, APointWithoutACellGoesLiveFromTheTemplateCaughtUpOnItsWholeMotion) {
  const std::vector<Mat2> motion = off_library_motion();
  auto law = surrogate_law(settings(median_tolerance(motion), 2));
  Driver d = new_point(*law);
  for (std::size_t k = 0; k < motion.size(); ++k) {
    d(*law, motion[k], kDt);
    if (k == 0 || law->source(d.slot) != StressSource::live) continue;  // step 0 starts from the template itself
    const dem::DemCell* cell = law->live_cell(d.slot);
    ASSERT_NE(cell, nullptr);
    EXPECT_LT((cell->deformation_gradient() - embed_plane_strain(d.F) * shared().cell->deformation_gradient()).norm(),
              1e-12);
    const CouplingCounters c = law->point_counters(d.slot);
    EXPECT_EQ(c.went_live, 1u);
    EXPECT_GT(c.warm_start_catch_up_steps, 0u);
    EXPECT_EQ(c.warm_start_servo_steps, 0u);
    EXPECT_EQ(c.warm_start_increments, 0u);
    return;
  }
  FAIL() << "the point never went live after its first step";
}

// Along a motion the library does not cover, a point that goes live starts from a servoed snapshot:
// no increment of its history is replayed, and its stress does not jump: the change of stress over
// the step on which it goes live exceeds the largest change over a step between two live steps of
// the same motion by at most the servo's tolerance. That tolerance is set on its own, 200 Pa: left to
// default to the law's (the median step estimate along the motion) it had grown to 505 kPa, and the
// check could not fail.
TEST(SurrogateLaw, APointGoesLiveFromAServoedSnapshotWithoutReplayOrJump) {
  const std::vector<Mat2> motion = off_library_motion();
  SurrogateLawSettings s = settings(median_tolerance(motion), 2);
  s.state_warm_start.first_cell = StateWarmStartSettings::FirstCell::nearest_snapshot;
  s.state_warm_start.stress_tolerance = 200;
  const double tolerance = s.state_warm_start.stress_tolerance;
  auto law = surrogate_law(s);
  Driver d = new_point(*law);
  double largest_live_step = 0, largest_jump = 0;
  int transitions = 0;
  for (std::size_t k = 0; k < motion.size(); ++k) {
    const PointStress before = d.stress;
    const bool was_live = law->source(d.slot) == StressSource::live;
    d(*law, motion[k], kDt);
    ASSERT_TRUE(d.stress.in_plane.allFinite());
    if (law->source(d.slot) != StressSource::live) continue;
    const double change = stress_distance(d.stress, before);
    if (was_live) {
      largest_live_step = std::max(largest_live_step, change);
    } else if (k > 0) {  // step 0 starts from the template itself
      largest_jump = std::max(largest_jump, change);
      ++transitions;
    }
  }
  std::printf("%d transitions to live: largest change %.0f Pa; largest live step %.0f Pa; tolerance %.0f Pa\n",
              transitions, largest_jump, largest_live_step, tolerance);
  const CouplingCounters c = law->point_counters(d.slot);
  ASSERT_GE(transitions, 1);
  ASSERT_GT(largest_live_step, 0.0);
  EXPECT_LE(largest_jump, largest_live_step + tolerance);
  EXPECT_EQ(c.servo_unconverged, 0u);
  EXPECT_EQ(c.warm_start_increments, 0u) << "nothing replayed";
  EXPECT_GT(c.warm_start_servo_steps, 0u);
}

// A solver holding one point of a surrogate law (restart files are written from a solver).
Solver one_point_solver(const SurrogateLawSettings& s) {
  Solver solver(Grid(Vec2(0, 0), 0.1, 6, 6), SolverSettings{});
  solver.add_law(surrogate_law(s));
  solver.add_point(0, Vec2(0.3, 0.3), 0.0025, 0.025, Vec2::Zero());
  return solver;
}

SurrogateLaw& law_of(Solver& solver) { return dynamic_cast<SurrogateLaw&>(solver.law(0)); }

TEST(SurrogateLaw, ARestartContinuesBitForBit) {
  // Compressed and sheared, then stretched: at half the motion's median estimated error the point
  // goes live, returns, and goes live again.
  std::vector<Mat2> motion(20, off_library_motion().front());
  motion.insert(motion.end(), 40, Mat2{{1.0, 0.0}, {0.0, 1.0}});
  // Live spells start from a cell servoed to the point's state, or by replay from the point's
  // checkpoint. With the state warm start the learned samples span three steps, so a restart inside a
  // spell must keep the steps its next sample spans.
  for (const auto warm_start : {SurrogateLawSettings::WarmStart::state, SurrogateLawSettings::WarmStart::replay}) {
    SCOPED_TRACE(warm_start == SurrogateLawSettings::WarmStart::state ? "state warm start" : "replay");
    SurrogateLawSettings s = settings(0.5 * median_tolerance(motion), 2);
    s.warm_start = warm_start;
    if (warm_start == SurrogateLawSettings::WarmStart::state) s.sample_span = 3;
    Solver straight = one_point_solver(s);
    Driver d;
    std::vector<PointStress> expected;
    std::vector<StressSource> sources;
    for (const Mat2& L : motion) {
      d(law_of(straight), L, kDt);
      expected.push_back(d.stress);
      sources.push_back(law_of(straight).source(0));
    }
    // Restart one step after the point first went live (its cell, history and learned samples
    // matter), and one step after it first handed its cell back, before it goes live again (the kept
    // cell or the checkpoint it will start from matters).
    const auto live = std::find(sources.begin(), sources.end(), StressSource::live);
    ASSERT_NE(live, sources.end());
    const auto back = std::find(live, sources.end(), StressSource::hit);
    ASSERT_NE(back, sources.end()) << "the point never returned to the surrogate";
    ASSERT_NE(std::find(back, sources.end(), StressSource::live), sources.end()) << "nor went live again";
    // And right after the spell's first step, whose successor's sample spans both (with the state
    // warm start).
    ASSERT_EQ(*(live + 1), StressSource::live) << "a spell lasts at least return_after steps";
    for (const auto restart_after : {static_cast<std::size_t>(live - sources.begin()) + 1,
                                     static_cast<std::size_t>(live - sources.begin()) + 2,
                                     static_cast<std::size_t>(back - sources.begin()) + 1}) {
      SCOPED_TRACE("restart after step " + std::to_string(restart_after));
      ASSERT_LT(restart_after, motion.size());
      Solver first = one_point_solver(s);
      Driver e;
      for (std::size_t k = 0; k < restart_after; ++k) e(law_of(first), motion[k], kDt);
      const std::filesystem::path file = shared().dir.path() / "restart.h5";
      io::write_restart(file, first);
      Solver resumed = one_point_solver(s);
      io::read_restart(file, resumed);
      EXPECT_EQ(law_of(resumed).learned(), law_of(first).learned());
      for (std::size_t k = restart_after; k < motion.size(); ++k) {
        e(law_of(resumed), motion[k], kDt);
        EXPECT_EQ(e.stress.in_plane, expected[k].in_plane) << "step " << k;
        EXPECT_EQ(e.stress.zz, expected[k].zz) << "step " << k;
        EXPECT_EQ(law_of(resumed).source(0), sources[k]) << "step " << k;
      }
      EXPECT_EQ(law_of(resumed).learned(), law_of(straight).learned());
      EXPECT_EQ(law_of(resumed).damage(0), law_of(straight).damage(0));
      // A replay after the restart starts where one in the straight run does: the same increments.
      EXPECT_EQ(law_of(resumed).point_counters(0).warm_start_increments,
                law_of(straight).point_counters(0).warm_start_increments -
                    law_of(first).point_counters(0).warm_start_increments);
    }
  }
}

std::filesystem::path write_scene(const std::string& material_extra, const std::string& fallback_extra = "") {
  const std::filesystem::path file = shared().dir.path() / "scene.json";
  std::ofstream(file) << R"({
  "grid": {"cell_size": 0.1, "cells": [6, 6]},
  "time": {"end": 0.001, "output_interval": 0.001},
  "integration": {"homogeneous_drive": {"L": [[-1, 2], [0, 0.5]], "origin": [0.3, 0.3]}},
  "materials": [{"name": "snow", "law": "surrogate", "library": ")" +
                             shared().path.string() + R"(", "template": )" +
                             std::to_string(shared().template_id) + R"(, "tolerance": 2000, "k": 16,
                 "fallback": {"return_after": 3)" + fallback_extra + "}" + material_extra + R"(}],
  "regions": [{"material": "snow", "rectangle": {"min": [0.2, 0.2], "max": [0.4, 0.4]}}]
})";
  return file;
}

TEST(SurrogateLaw, ASceneNamesTheLawAndItsKeysAreChecked) {
  const io::Scene scene = io::load_scene(write_scene(""));
  ASSERT_FALSE(scene.solver->points().empty());
  const auto& law = dynamic_cast<const SurrogateLaw&>(scene.solver->law(0));
  EXPECT_EQ(law.name(), "surrogate");
  EXPECT_EQ(law.index().options().k, 16u);
  EXPECT_EQ(law.index().size(), shared().dataset.samples.size());
  // Stepped by the solver (its points updated in parallel): every point-step is answered once.
  for (int k = 0; k < 3; ++k) scene.solver->step(kDt);
  CouplingCounters total;
  for (const MaterialPoint& mp : scene.solver->points()) {
    total += law.point_counters(mp.slot);
    EXPECT_TRUE(mp.stress.in_plane.allFinite());
  }
  std::printf("%zu points, 3 steps: %llu hits, %llu live updates, %llu went live\n", scene.solver->points().size(),
              static_cast<unsigned long long>(total.hits), static_cast<unsigned long long>(total.live_updates),
              static_cast<unsigned long long>(total.went_live));
  EXPECT_EQ(total.hits + total.live_updates, 3 * scene.solver->points().size());
  EXPECT_EQ(law.index().size(), shared().dataset.samples.size() + law.learned());
  try {
    io::load_scene(write_scene(R"(, "lookup": {"k": 4})"));
    FAIL() << "an unknown key was accepted";
  } catch (const common::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/materials/0/lookup: unknown key"), std::string::npos) << e.what();
  }
  EXPECT_NE(law.state_warm_start(), nullptr) << "the default warm start is by state";
  const io::Scene replaying = io::load_scene(write_scene("", R"(, "warm_start": "replay")"));
  EXPECT_EQ(dynamic_cast<const SurrogateLaw&>(replaying.solver->law(0)).state_warm_start(), nullptr);
  try {
    io::load_scene(write_scene("", R"(, "warm_start": "sideways")"));
    FAIL() << "an unknown warm start was accepted";
  } catch (const common::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/materials/0/fallback/warm_start"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("\"replay\""), std::string::npos) << e.what();
  }
  const std::pair<const char*, const char*> refused[] = {{R"(, "catch_up_steps": 0)", "/fallback/catch_up_steps"},
                                                          {R"(, "catch_up_legs": 0)", "/fallback/catch_up_legs"},
                                                          {R"(, "first_cell": "nearest")", "/fallback/first_cell"}};
  for (const auto& [fallback, named] : refused) {
    try {
      io::load_scene(write_scene("", fallback));
      FAIL() << fallback << " was accepted";
    } catch (const common::InputError& e) {
      EXPECT_NE(std::string(e.what()).find(std::string("/materials/0") + named), std::string::npos) << e.what();
    }
  }
  // A point's first cell is the template caught up by default; the library's snapshots are read only
  // for first_cell "snapshot".
  EXPECT_EQ(law.state_warm_start()->size(), 1u);
  const io::Scene from_snapshots = io::load_scene(write_scene("", R"(, "first_cell": "snapshot")"));
  EXPECT_EQ(dynamic_cast<const SurrogateLaw&>(from_snapshots.solver->law(0)).state_warm_start()->size(),
            shared().snapshots.size() + 1);
}

}  // namespace
}  // namespace grainbank::mpm
