// Integrating the surrogate's rate answers along a stored path's own velocity gradients (the point
// carries its state, issue 13) reproduces that path's stress within the accumulated estimated error.
//
// The library: forty generated two-segment paths (loading, then reversal or a turn of the axes),
// all indexed. Each path is integrated from its first record with surrogate_step; at every record k
// the integrated stress is compared (in-plane and σ_zz) with the stored one. Two accumulations of
// the per-step estimates e_j: the bound Σ_{j≤k} e_j (every step wrong in the same direction) and the
// random walk (Σ_{j≤k} e_j²)^½ (independent errors), which fails where the steps share a bias.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "dem_sampler/cell/matrix_functions.hpp"
#include "database/store/library.hpp"
#include "database/surrogate/surrogate_step.hpp"
#include "tests/database/surrogate_test_util.hpp"

namespace grainbank::surrogate {
namespace {

TEST(SurrogateIntegration, AStoredPathIsReproducedWithinTheEstimatedError) {
  const test::TempDir dir("grainbank-surrogate-integration");
  db::Library library = test::build_library(dir, dir.path() / "LIB", test::kGeneralPaths);
  const Dataset dataset = reindex(library);
  const auto index = test::fitted_index(dataset);

  int paths = 0, records_checked = 0, within_bound = 0, within_walk = 0;
  double worst_relative = 0;  // max over paths of max_k error / max_k |σ_k − σ_0|
  for (const db::PathRow& path : library.catalogue().paths()) {
    const std::vector<db::Record> records = library.records(path.id);
    const dem::Mat3 start = test::answered_part(db::from_stress6(records.front().stress));
    PointState state = point_state(records.front());
    double bound = 0, walk2 = 0, worst_error = 0, excursion = 0;
    for (std::size_t k = 0; k + 1 < records.size(); ++k) {
      const SurrogateStep step = surrogate_step(*index, state, records[k + 1].L, records[k + 1].time - records[k].time, 0);
      state = step.state;
      bound += step.estimated_error;
      walk2 += step.estimated_error * step.estimated_error;
      const dem::Mat3 target = test::answered_part(db::from_stress6(records[k + 1].stress));
      const double error = (test::answered_part(state.stress) - target).norm();
      ++records_checked;
      within_bound += error <= bound;
      within_walk += error <= std::sqrt(walk2);
      worst_error = std::max(worst_error, error);
      excursion = std::max(excursion, (target - start).norm());
    }
    worst_relative = std::max(worst_relative, worst_error / excursion);
    ++paths;
  }
  std::printf("%d paths, %d records: within the bound %d, within the random walk %d; worst error / excursion %.3f\n",
              paths, records_checked, within_bound, within_walk, worst_relative);
  EXPECT_EQ(paths, 40);
  // The library is a chaotic DEM system's output, so these figures move with the last bits of the
  // engine, and a build's floating-point path draws another library. Over packing seeds 1-16 of the
  // cell (stop 61), within the bound: 94.8-99.6 % in the native build here, 92.8-99.4 % in a portable
  // one (no FMA outside the force loop); within the random walk 69.9-86.1 % and 55.0-82.9 %. The
  // thresholds hold over those 32 draws. The misses are first steps out of the template at rest,
  // where forty paths start from one state in forty directions.
  EXPECT_GE(within_bound, 0.90 * records_checked);
  EXPECT_GE(within_walk, 0.50 * records_checked);
  // The worst path is reproduced to within its own excursion (5-7 kPa); over seeds 3-8 the worst
  // ratio was 0.14-0.80, so this bounds blunders, not the typical accuracy.
  EXPECT_LT(worst_relative, 1.0);
}

// Stability: answers scale with p, so a fit that extrapolates stiffer than its samples would grow the
// stress exponentially (before the bound, along this motion: σ_xx from −8 kPa to −1.9 MPa in 60
// steps). Driven with no tolerance along a motion its 0.4 % paths do not cover (6 % of strain), no
// step's stress change exceeds the stiffest sample's ‖σ̇ᴶ‖/|D| times the step's |D| Δt.
TEST(SurrogateIntegration, NoStepIsStifferThanTheStiffestSample) {
  const test::TempDir dir("grainbank-surrogate-stiffness");
  db::Library library = test::build_library(dir, dir.path() / "LIB", test::kGeneralPaths);
  const auto index = test::fitted_index(reindex(library));
  const double stiffest = index->largest_stiffness();
  ASSERT_GT(stiffest, 0.0);
  dem::Mat3 L = dem::Mat3::Zero();
  L(0, 0) = -1.5, L(0, 1) = 1.0, L(1, 1) = 0.5;
  const double dt = 2e-4, rate = (0.5 * (L + L.transpose())).norm();
  PointState state = point_state(library.records(library.catalogue().paths().front().id).front());
  double largest_ratio = 0;
  for (int step = 0; step < 180; ++step) {
    const SurrogateStep next = surrogate_step(*index, state, L, dt, std::numeric_limits<double>::infinity());
    // The Jaumann part of the change: undo the step's spin before comparing.
    const dem::Mat3 R = dem::matrix_exponential(0.5 * (L - L.transpose()) * dt);
    const dem::Mat3 change = test::answered_part(R.transpose() * next.state.stress * R - state.stress);
    largest_ratio = std::max(largest_ratio, change.norm() / (stiffest * rate * dt));
    ASSERT_TRUE(next.state.stress.allFinite());
    state = next.state;
  }
  std::printf("largest stress change per step / (stiffest sample × |D| dt): %.3f; final |σ| %.0f Pa\n", largest_ratio,
              state.stress.norm());
  EXPECT_LE(largest_ratio, 1 + 1e-6);
}

}  // namespace
}  // namespace grainbank::surrogate
