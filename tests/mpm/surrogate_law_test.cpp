// The surrogate law's answers (issue 13), on the fixture's small real library:
// - a point driven along each stored path's own velocity gradients follows that path's stress
//   within the error the law estimates, summed over the steps;
// - with tolerance 0 every step is live and the law is the live law;
// - live responses learned by one point let a second point along the same motion hit more;
// - tension beyond the library is an off-library state; a step does not depend on the order its
//   points are updated in; an error budget bounds the errors spent between live steps.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "tests/mpm/surrogate_law_fixture.hpp"
#include "mpm_solver/dem_laws/live_dem_law.hpp"
#include "database/surrogate/surrogate_step.hpp"

namespace grainbank::mpm {
namespace {

using namespace surrogate_law_fixture;

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
  // As database.surrogate_integration measures on the same library, with its threshold (it holds
  // over 32 draws of the library: packing seeds and builds): the misses are first steps out of the
  // template at rest, where forty paths leave one state in forty directions.
  EXPECT_GE(within, 0.90 * records);
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
// re-anchored on a cell, and nothing is replayed; a step whose own error still exceeds the budget
// from the re-anchored state goes live on that cell for a spell of the budget (in the native build
// here no step does; a portable build took one of 1.6 MPa against a budget of 0.95 MPa before the
// law ran such a step live).
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
      EXPECT_EQ(c.went_live_on_budget, c.went_live) << "with no tolerance, only the budget sends a point live";
      // A step beyond the budget alone starts a spell of the budget: that step and one more.
      EXPECT_LE(c.live_updates, 2 * c.went_live);
      EXPECT_LT(c.went_live, c.reanchored);
      EXPECT_EQ(c.warm_start_increments, 0u);
      // The first re-anchoring catches the template up on the point's whole motion, the later ones
      // the point's own cell on its motion since: nothing is servoed.
      EXPECT_EQ(c.warm_start_servo_steps, 0u);
      EXPECT_GT(c.warm_start_catch_up_steps, 0u);
    }
  }
}

}  // namespace
}  // namespace grainbank::mpm
