// Re-tiling: the supercell is the same infinite packing (stress, contacts and bonds per sphere, F),
// its Verlet list is the one a fresh build finds, its copies move as the original, a cell flattened
// past the thin limit goes on, the cap stops it as before, and a restart across a re-tiling is exact.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <cstdio>
#include <set>
#include <tuple>

#include "dem_sampler/cell/periodic_cell.hpp"
#include "dem_sampler/cell/retiling.hpp"
#include "dem_sampler/cell/verlet_list.hpp"
#include "tests/dem/dem_test_util.hpp"

namespace grainbank::dem {
namespace {

// A bonded 64-sphere cell sheared a little, so that contacts and bonds carry tangential history.
DemCell sheared_bonded_cell() {
  const Material mat = test::small_material(true);
  DemCell cell = prepare_cell(mat, test::small_spec(64, 31));
  for (int k = 0; k < 20; ++k) cell.advance(test::simple_shear(2e-4), 1e-5, Substepping{});
  return cell;
}

// Plane-strain flattening: y shrinks, x grows, by exp(∓ε).
Mat3 flattening(double strain) {
  Mat3 f = Mat3::Identity();
  f(0, 0) = std::exp(strain);
  f(1, 1) = std::exp(-strain);
  return f;
}

std::set<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>> pair_keys(const CellState& st) {
  std::set<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>> keys;
  for (const Pair& p : st.pairs) keys.insert({p.i, p.j, p.image});
  return keys;
}

// The positions and velocities of `st` alone: the DemCell constructor builds a fresh list.
CellState without_list(CellState st) {
  st.pairs.clear();
  st.bonds.clear();
  st.rolling_moment.clear();
  st.force.clear();
  st.torque.clear();
  st.reduced_position_at_list_build.clear();
  return st;
}

TEST(Retiling, TheSupercellIsTheSamePacking) {
  const DemCell cell = sheared_bonded_cell();
  const CellMeasures before = cell.measures();
  ASSERT_GT(before.bonds, 0);
  for (int axis = 0; axis < 3; ++axis) {
    SCOPED_TRACE("axis " + std::to_string(axis));
    DemCell big(doubled_along(cell.state(), axis), cell.material(), cell.skin());
    EXPECT_EQ(big.size(), 2 * cell.size());
    EXPECT_NEAR(big.volume(), 2 * cell.volume(), 1e-12 * cell.volume());
    EXPECT_LT((big.deformation_gradient() - cell.deformation_gradient()).norm(), 1e-12);
    EXPECT_EQ(big.contact_count(), 2 * cell.contact_count());
    const CellMeasures m = big.measures();
    EXPECT_EQ(m.bonds, 2 * before.bonds);
    EXPECT_DOUBLE_EQ(m.damage, before.damage);
    EXPECT_NEAR(m.solid_fraction, before.solid_fraction, 1e-12);

    // The same step on both recomputes every force from the (mapped) pair list: equal stress.
    DemCell small = cell;
    const Mat3 L = test::simple_shear(10.0) - Mat3::Identity();
    const double dt = 0.5 * cell.time_step(0.1);
    small.step_with_velocity_gradient(L, dt);
    big.step_with_velocity_gradient(L, dt);
    EXPECT_LT(test::rel_diff(big.stress(), small.stress()), 1e-12);
    EXPECT_DOUBLE_EQ(big.measures().coordination, small.measures().coordination);

    // The mapped list of a freshly built list is the one a fresh build of the supercell finds.
    const DemCell small_fresh(without_list(cell.state()), cell.material(), cell.skin());
    const CellState mapped = doubled_along(small_fresh.state(), axis);
    const DemCell big_fresh(without_list(mapped), cell.material(), cell.skin());
    EXPECT_EQ(pair_keys(big_fresh.state()), pair_keys(mapped));
  }
}

TEST(Retiling, TheCopiesMoveAsTheOriginalAlongTheSamePath) {
  DemCell small = sheared_bonded_cell();
  const int axis = 2;
  DemCell big(doubled_along(small.state(), axis), small.material(), small.skin());
  const Vec3 a = small.cell_matrix().col(axis);
  for (int k = 0; k < 10; ++k) {
    const IncrementResult rs = small.advance(test::simple_shear(2e-4) * flattening(1e-4), 1e-5, Substepping{});
    const IncrementResult rb = big.advance(test::simple_shear(2e-4) * flattening(1e-4), 1e-5, Substepping{});
    ASSERT_EQ(rb.substeps, rs.substeps);
    EXPECT_LT(test::rel_diff(rb.stress, rs.stress), 1e-9) << "increment " << k;
  }
  const std::size_t n = small.size();
  const std::vector<Vec3> xs = small.positions(), xb = big.positions();
  double worst = 0;
  for (std::size_t p = 0; p < n; ++p) {
    // Positions are unwrapped in different cells; compare modulo the small cell's lattice.
    auto lattice_residual = [&](const Vec3& d) {
      Vec3 s = small.cell_matrix().inverse() * d;
      for (int c = 0; c < 3; ++c) s[c] -= std::round(s[c]);
      return (small.cell_matrix() * s).norm();
    };
    worst = std::max({worst, lattice_residual(xb[p] - xs[p]), lattice_residual(xb[p + n] - xs[p] - a)});
  }
  EXPECT_LT(worst, 1e-9 * test::small_spec(64, 31).min_diameter);
}

TEST(Retiling, ARetiledCellShearsLikeCellsTwiceAsLarge) {
  // Simple shear to γ = 0.3: the friction mobilized (σ_xy / p averaged over the second half of the
  // path) of re-tiled 32 -> 64-sphere cells against 64-sphere cells prepared with other seeds, four
  // of each. A re-tiled cell is one 32-sphere packing repeated, so its seed spread is wider (√2 for
  // Gaussian noise); the two means must agree within three standard errors of their difference.
  const Material mat = test::small_material(true);
  auto mobilized_friction = [&](DemCell cell) {
    double sum = 0;
    int count = 0;
    for (int k = 0; k < 60; ++k) {
      const IncrementResult r = cell.advance(test::simple_shear(0.005), 5e-4, Substepping{});
      if (k >= 30) sum += r.stress(0, 1) / pressure_of(r.stress), ++count;
    }
    return std::abs(sum / count);
  };
  std::vector<double> fresh, retiled;
  for (std::uint64_t seed : {41, 42, 43, 44})
    fresh.push_back(mobilized_friction(prepare_cell(mat, test::small_spec(64, seed))));
  for (std::uint64_t seed : {45, 46, 47, 48}) {
    const DemCell half = prepare_cell(mat, test::small_spec(32, seed));
    retiled.push_back(
        mobilized_friction(DemCell(doubled_along(half.state(), thinnest_axis(half.cell_matrix())), mat, half.skin())));
  }
  auto mean = [](const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0) / v.size(); };
  auto variance_of_mean = [&](const std::vector<double>& v) {
    const double m = mean(v);
    double s2 = 0;
    for (double x : v) s2 += (x - m) * (x - m);
    return s2 / (v.size() - 1) / v.size();
  };
  const double standard_error = std::sqrt(variance_of_mean(fresh) + variance_of_mean(retiled));
  std::printf("σ_xy/p: fresh 64-sphere cells %.3f %.3f %.3f %.3f, re-tiled 32 -> 64 %.3f %.3f %.3f %.3f\n", fresh[0],
              fresh[1], fresh[2], fresh[3], retiled[0], retiled[1], retiled[2], retiled[3]);
  EXPECT_GT(standard_error, 0);
  EXPECT_LT(std::abs(mean(retiled) - mean(fresh)), 3 * standard_error);
}

TEST(Retiling, AFlattenedCellGoesOnPastTheThinLimitAndTheCapStopsItAsBefore) {
  const Material mat = test::small_material(true);
  const DemCell prepared = prepare_cell(mat, test::small_spec(64, 33));
  const double rate = 200;  // 1/s: I ~ 0.01 at 10 kPa with 1 mm grains
  auto flatten = [&](DemCell cell, double strain) {
    const double step = 0.01;
    for (double e = 0; e < strain - 1e-12; e += step) cell.advance(flattening(step), step / rate, Substepping{});
    return cell;
  };
  EXPECT_THROW(flatten(prepared, 1.0), CellTooThinError) << "without re-tiling the cell gets too thin";
  DemCell capped = prepared;
  capped.set_retiling_cap(prepared.size());  // no room to double
  EXPECT_THROW(flatten(capped, 1.0), CellTooThinError);

  DemCell open = prepared;
  open.set_retiling_cap(1024);
  const DemCell done = flatten(open, 1.0);
  EXPECT_GE(done.size(), 2 * prepared.size());
  EXPECT_NEAR(done.deformation_gradient()(1, 1), std::exp(-1.0), 1e-9);
  EXPECT_NEAR(done.deformation_gradient()(0, 0), std::exp(1.0), 1e-9);
  const Vec3 width = perpendicular_widths(done.cell_matrix());
  const double cutoff = 2 * *std::max_element(done.radii().begin(), done.radii().end()) + done.skin();
  EXPECT_GE(width.minCoeff(), 2 * cutoff);
  const CellMeasures m = done.measures();
  EXPECT_TRUE(m.stress.allFinite());
  EXPECT_GT(pressure_of(m.stress), 0) << "a flattened packing at constant volume stays in compression";
  EXPECT_NEAR(m.solid_fraction, prepared.measures().solid_fraction, 1e-9) << "plane strain at constant volume";
}

TEST(Retiling, PureShearToALogStrainOfTwoAndAHalfCompletes) {
  // The y width shrinks by exp(-2.5) = 1/12: four doublings of a 64-sphere cell.
  const Material mat = test::small_material(true);
  DemCell cell = prepare_cell(mat, test::small_spec(64, 37));
  const double solid_fraction = cell.measures().solid_fraction;
  cell.set_retiling_cap(4096);
  const double rate = 200, step = 0.02;
  for (int k = 0; k < 125; ++k) cell.advance(flattening(step), step / rate, Substepping{});
  std::printf("log strain 2.5: %zu spheres, %lld flips\n", cell.size(), static_cast<long long>(cell.flips()));
  EXPECT_GE(cell.size(), 16u * 64u);
  EXPECT_NEAR(cell.deformation_gradient()(1, 1), std::exp(-2.5), 1e-9);
  const CellMeasures m = cell.measures();
  EXPECT_TRUE(m.stress.allFinite());
  EXPECT_GT(pressure_of(m.stress), 0);
  EXPECT_NEAR(m.solid_fraction, solid_fraction, 1e-9);
}

TEST(Retiling, RestartAcrossAReTilingIsExact) {
  const Material mat = test::small_material(true);
  DemCell cell = prepare_cell(mat, test::small_spec(64, 35));
  cell.set_retiling_cap(1024);
  const double rate = 200, step = 0.01;
  auto drive = [&](DemCell& c, int increments) {
    for (int k = 0; k < increments; ++k) c.advance(flattening(step), step / rate, Substepping{});
  };
  std::size_t n0 = cell.size();
  int before = 0;
  // Drive to just before the first re-tiling, checkpoint, then go through it both ways.
  for (;; ++before) {
    DemCell probe = cell;
    drive(probe, 1);
    if (probe.size() > n0) break;
    cell = probe;
    ASSERT_LT(before, 200) << "the cell never re-tiled";
  }
  DemCell restarted(cell.state(), mat, cell.skin());
  restarted.set_retiling_cap(1024);
  drive(cell, 5);
  drive(restarted, 5);
  ASSERT_GT(cell.size(), n0);
  std::string why;
  EXPECT_TRUE(test::states_identical(cell.state(), restarted.state(), &why)) << why;
}

}  // namespace
}  // namespace grainbank::dem
