// A live DEM point driven toward a cell only a few grains thick. Simple shear never gets there (the
// cell flips to a reduced basis and goes on); flattening does, and the run must then stop with an
// error naming the material point, the quantity (the cell's width against its interaction range)
// and the remedy, with every stress finite up to that step, unless re-tiling is on: then the cell
// doubles along its thin width and the point goes on, its volume and F still the point's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "dem_sampler/cell/preparation.hpp"
#include "dem_sampler/cell/snow_preset.hpp"
#include "mpm_solver/dem_laws/live_dem_law.hpp"
#include "tests/mpm/mpm_test_util.hpp"

namespace grainbank::mpm {
namespace {

// One live point (30-sphere snow cell) in a domain deformed homogeneously at L.
Solver driven_live_point(const dem::DemCell& cell_template, const Mat2& L, LiveDemSettings settings = {}) {
  Solver solver(Grid(Vec2(0, 0), 0.1, 8, 8), SolverSettings{});
  const std::size_t law = solver.add_law(std::make_unique<LiveDemLaw>(cell_template, settings));
  solver.add_point(law, Vec2(0.43, 0.37), 1e-2, 0.05);
  solver.set_homogeneous_drive(HomogeneousDrive{L, Vec2(0.43, 0.37), std::nullopt});
  return solver;
}

const dem::DemCell& snow_cell() {
  static const dem::DemCell cell = dem::prepare_cell(dem::snow_material(), dem::snow_preparation(30, 5));
  return cell;
}

TEST(HardCasesLive, SimpleShearedLiveCellFlipsInsteadOfThinning) {
  Mat2 L;
  L << 0, 40, 0, 0;  // γ = 0.6 over 0.015 s: the tilt passes one half
  Solver solver = driven_live_point(snow_cell(), L);
  ASSERT_NO_THROW(testing::run_until(solver, 0.015, [](const Solver& s) {
    ASSERT_TRUE(s.points()[0].stress.in_plane.allFinite());
  }));
  const auto& law = dynamic_cast<const LiveDemLaw&>(solver.law(0));
  EXPECT_GE(law.cell(0).flips(), 1);
  EXPECT_NEAR(law.cell(0).deformation_gradient()(0, 1), solver.points()[0].deformation_gradient(0, 1), 1e-9);
}

TEST(HardCasesLive, FlattenedLiveCellStopsNamingThePointTheWidthAndTheRemedy) {
  // Plane-strain flattening ε_yy = -ε_xx: the y width of the ~3-grain cell falls below twice the
  // interaction range (largest diameter + skin) after about 25 % strain.
  Mat2 L;
  L << 10, 0, 0, -10;
  Solver solver = driven_live_point(snow_cell(), L);
  long steps = 0;
  try {
    testing::run_until(solver, 0.1, [&](const Solver& s) {
      ASSERT_TRUE(s.points()[0].stress.in_plane.allFinite()) << "step " << s.steps();
      ASSERT_TRUE(std::isfinite(s.points()[0].volume));
      steps = s.steps();
    });
    FAIL() << "a cell thinner than two interaction ranges was driven on";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    std::printf("after %ld steps, t = %g s: %s\n", steps, solver.time(), what.c_str());
    EXPECT_NE(what.find("material point 0 (law live)"), std::string::npos) << what;
    EXPECT_NE(what.find("periodic cell too thin"), std::string::npos) << what;
    EXPECT_NE(what.find("smallest width"), std::string::npos) << what;
    EXPECT_NE(what.find("more spheres"), std::string::npos) << what;
  }
  EXPECT_GT(solver.time(), 0.015) << "the cell stops only when really thin, not at the first squeeze";
}

TEST(HardCasesLive, FlattenedLiveCellReTilesAndGoesOnAsTheSameMaterial) {
  Mat2 L;
  L << 10, 0, 0, -10;  // plane strain at constant volume, to a log strain of 1 at t = 0.1 s
  LiveDemSettings settings;
  settings.max_spheres = 30 * 16;
  Solver solver = driven_live_point(snow_cell(), L, settings);
  const double volume0 = solver.points()[0].volume;
  ASSERT_NO_THROW(testing::run_until(solver, 0.1, [](const Solver& s) {
    ASSERT_TRUE(s.points()[0].stress.in_plane.allFinite()) << "step " << s.steps();
  }));
  const auto& law = dynamic_cast<const LiveDemLaw&>(solver.law(0));
  const dem::DemCell& cell = law.cell(0);
  const std::uint64_t doublings = law.point_counters(0).retilings;
  std::printf("t = %g s: %zu spheres, %llu re-tilings\n", solver.time(), cell.size(),
              static_cast<unsigned long long>(doublings));
  EXPECT_GE(doublings, 1u);
  EXPECT_EQ(cell.size(), snow_cell().size() << doublings);
  EXPECT_NEAR(solver.points()[0].volume, volume0, 1e-6 * volume0) << "the copies are not more material";
  EXPECT_NEAR(cell.deformation_gradient()(1, 1), solver.points()[0].deformation_gradient(1, 1), 1e-9);
  EXPECT_NEAR(solver.points()[0].deformation_gradient(1, 1), std::exp(-10 * solver.time()), 1e-6);
}

TEST(HardCasesLive, ACapBelowTheFirstDoublingStopsTheFlattenedCellAsWithoutReTiling) {
  Mat2 L;
  L << 10, 0, 0, -10;
  LiveDemSettings settings;
  settings.max_spheres = 2 * 30 - 1;
  Solver solver = driven_live_point(snow_cell(), L, settings);
  EXPECT_THROW(testing::run_until(solver, 0.1, [](const Solver&) {}), std::runtime_error);
  EXPECT_EQ(dynamic_cast<const LiveDemLaw&>(solver.law(0)).cell(0).size(), snow_cell().size());
}

TEST(HardCasesLive, PastTheCapTheFlattenedCellIsRegeneratedAndTheMaterialGoesOn) {
  Mat2 L;
  L << 10, 0, 0, -10;  // to a log strain of 1 at t = 0.1 s; without a new cell it stops near 0.025 s
  LiveDemSettings settings;
  settings.max_spheres = 2 * 30;  // one doubling, then regeneration
  settings.regenerate_beyond_cap = true;
  Solver solver = driven_live_point(snow_cell(), L, settings);
  const auto& law = dynamic_cast<const LiveDemLaw&>(solver.law(0));
  const double volume0 = solver.points()[0].volume;
  // Per step: the largest change of a stress component, and whether the cell was regenerated.
  std::vector<double> change;
  std::vector<Mat2> stress{solver.points()[0].stress.in_plane};
  std::vector<std::size_t> regenerated_at;
  std::vector<bool> converged;  // per regeneration: did the servo reach the worn cell's stress
  std::uint64_t unconverged_so_far = 0;
  ASSERT_NO_THROW(testing::run_until(solver, 0.1, [&](const Solver& s) {
    const Mat2& now = s.points()[0].stress.in_plane;
    ASSERT_TRUE(now.allFinite()) << "step " << s.steps();
    ASSERT_LE(law.cell(0).size(), settings.max_spheres);
    change.push_back((now - stress.back()).cwiseAbs().maxCoeff());
    stress.push_back(now);
    if (law.point_counters(0).regenerations > regenerated_at.size()) {
      regenerated_at.push_back(change.size() - 1);
      const std::uint64_t unconverged = law.point_counters(0).regenerations_unconverged;
      converged.push_back(unconverged == unconverged_so_far);
      unconverged_so_far = unconverged;
    }
  }));
  const CouplingCounters c = law.point_counters(0);
  std::printf("t = %g s: %llu re-tilings, %llu regenerations (%llu unconverged)\n", solver.time(),
              static_cast<unsigned long long>(c.retilings), static_cast<unsigned long long>(c.regenerations),
              static_cast<unsigned long long>(c.regenerations_unconverged));
  ASSERT_GE(regenerated_at.size(), 1u);
  EXPECT_GE(c.retilings, 1u) << "the cap allowed one doubling first";
  // The new cell keeps the point's F, so its volume: the drive is isochoric.
  EXPECT_NEAR(solver.points()[0].volume, volume0, 1e-6 * volume0);
  EXPECT_NEAR(law.cell(0).deformation_gradient()(1, 1), solver.points()[0].deformation_gradient(1, 1), 1e-9);
  // The new cell carries the worn one's stress: at a regeneration the point's stress moves by no more
  // than an ordinary step of the 20 before it plus the servo's tolerance (5 % of the stress scale).
  // A servo that stops short (a fresh 30-sphere cell may not hold the flattened cell's anisotropic
  // stress; regeneration.hpp leaves it where it stopped) promises less: the jump stays below half
  // the stress scale, so the point goes on from a stress of the right size and sign.
  for (std::size_t r = 0; r < regenerated_at.size(); ++r) {
    const std::size_t k = regenerated_at[r];
    ASSERT_GE(k, 20u);
    const double ordinary = *std::max_element(change.begin() + static_cast<long>(k) - 20, change.begin() + static_cast<long>(k));
    const double scale = stress[k].cwiseAbs().maxCoeff();
    std::printf("regeneration at step %zu (%s): stress moved %.1f Pa; ordinary steps before it up to %.1f Pa, scale %.1f Pa\n",
                k + 1, converged[r] ? "converged" : "servo stopped short", change[k], ordinary, scale);
    EXPECT_LE(change[k], ordinary + (converged[r] ? 0.05 : 0.5) * scale);
  }
}

}  // namespace
}  // namespace grainbank::mpm
