// The nonlocal average of the velocity gradient (core/nonlocal_average.hpp): exact for uniform and,
// inside the body, for linear fields; symmetric, so the body's total deformation rate is kept; blind to
// other materials; and a velocity jump across a band of one grid cell drives the band at a rate set by
// ℓ, not by h, which is what regularizes a softening law. An elastic column regularized over four grid
// cells settles to the same geostatic stress as a local one, without grid-scale modes.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "mpm_solver/core/nonlocal_average.hpp"
#include "tests/mpm/mpm_test_util.hpp"

namespace grainbank::mpm {
namespace {

// Points on a square lattice of spacing h filling [0, size]², volume h² each, law 0.
std::vector<MaterialPoint> lattice(double h, double size) {
  std::vector<MaterialPoint> points;
  const int n = static_cast<int>(std::lround(size / h));
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      MaterialPoint mp;
      mp.id = static_cast<std::uint32_t>(points.size());
      mp.position = Vec2((i + 0.5) * h, (j + 0.5) * h);
      mp.volume = h * h;
      points.push_back(mp);
    }
  return points;
}

TEST(NonlocalAverage, RefusesANonPositiveLength) {
  EXPECT_THROW(NonlocalAverage(0), std::invalid_argument);
  EXPECT_THROW(NonlocalAverage(-1), std::invalid_argument);
  EXPECT_THROW(NonlocalAverage(std::nan("")), std::invalid_argument);
}

TEST(NonlocalAverage, KeepsAUniformGradientEverywhereAndALinearOneInside) {
  const double h = 0.05, size = 1.0, length = 0.2;
  Mat2 uniform;
  uniform << 1, 2, -3, 0.5;
  std::vector<MaterialPoint> points = lattice(h, size);
  for (MaterialPoint& mp : points) mp.velocity_gradient = uniform;
  NonlocalAverage(length).apply(points);
  for (const MaterialPoint& mp : points) EXPECT_LT((mp.velocity_gradient - uniform).norm(), 1e-12);

  // L = A x + B y: the symmetric weight keeps it where the neighbourhood is whole.
  Mat2 a, b;
  a << 1, 0, 2, -1;
  b << 0, 3, 1, 1;
  for (MaterialPoint& mp : points) mp.velocity_gradient = a * mp.position.x() + b * mp.position.y();
  NonlocalAverage(length).apply(points);
  int inside = 0;
  for (const MaterialPoint& mp : points) {
    const Vec2& x = mp.position;
    if (x.minCoeff() < length || x.maxCoeff() > size - length) continue;
    EXPECT_LT((mp.velocity_gradient - (a * x.x() + b * x.y())).norm(), 1e-10);
    ++inside;
  }
  EXPECT_GT(inside, 100);
}

TEST(NonlocalAverage, ALengthBelowThePointSpacingLeavesEveryPointLocal) {
  std::vector<MaterialPoint> points = lattice(0.05, 1.0);
  for (MaterialPoint& mp : points) mp.velocity_gradient = mp.position.x() * Mat2::Identity();
  NonlocalAverage(1e-9).apply(points);  // also: bins of 1e-9 m would be 1e18 of them
  for (const MaterialPoint& mp : points)
    EXPECT_LT((mp.velocity_gradient - mp.position.x() * Mat2::Identity()).norm(), 1e-14);
}

// The averaging is symmetric (V_p α_pq = V_q α_qp, rows summing to one), so it only moves deformation
// between points: Σ V L̄ = Σ V L, boundaries included, for any field. Here a field with a jump, on a
// body with unequal point volumes.
TEST(NonlocalAverage, NeitherMakesNorLosesDeformation) {
  std::vector<MaterialPoint> points = lattice(0.05, 1.0);
  Mat2 before = Mat2::Zero(), after = Mat2::Zero();
  for (MaterialPoint& mp : points) {
    mp.volume *= 1 + 0.5 * std::sin(40 * mp.position.y());
    mp.velocity_gradient << std::cos(7 * mp.position.x()), mp.position.y() > 0.3 ? 2 : -1, mp.position.x(), 0.5;
    before += mp.volume * mp.velocity_gradient;
  }
  NonlocalAverage(0.2).apply(points);
  for (const MaterialPoint& mp : points) after += mp.volume * mp.velocity_gradient;
  EXPECT_LT((after - before).norm(), 1e-12 * before.norm());
}

TEST(NonlocalAverage, DoesNotMixMaterials) {
  std::vector<MaterialPoint> points = lattice(0.05, 1.0);
  for (MaterialPoint& mp : points) {
    mp.law = mp.position.x() < 0.5 ? 0 : 1;
    mp.velocity_gradient = (mp.law == 0 ? 1.0 : -2.0) * Mat2::Identity();
  }
  NonlocalAverage(0.2).apply(points);
  for (const MaterialPoint& mp : points)
    EXPECT_LT((mp.velocity_gradient - (mp.law == 0 ? 1.0 : -2.0) * Mat2::Identity()).norm(), 1e-12);
}

// A shear band of one lattice row carries a velocity jump Δv (L_xy = Δv/h there, 0 elsewhere). Inside
// the body the average at the band is Δv ∫ w(x, 0) dx / ∫ w dA = Δv (2ℓ/3) / (πℓ²/7) = 14 Δv / (3πℓ):
// independent of h, where the local rate Δv/h grows without bound.
TEST(NonlocalAverage, DrivesABandOfOneCellAtARateSetByTheLength) {
  const double length = 0.2, jump = 1.0, size = 1.0;
  const double expected = 14 * jump / (3 * std::numbers::pi * length);
  for (const double h : {length / 5, length / 10, length / 20}) {
    std::vector<MaterialPoint> points = lattice(h, size);
    const double band = (std::floor(0.5 * size / h) + 0.5) * h;  // a lattice row at mid-height
    for (MaterialPoint& mp : points)
      if (std::abs(mp.position.y() - band) < 0.25 * h) mp.velocity_gradient(0, 1) = jump / h;
    NonlocalAverage(length).apply(points);
    for (const MaterialPoint& mp : points) {
      if (std::abs(mp.position.y() - band) > 0.25 * h || std::abs(mp.position.x() - 0.5) > 0.1) continue;
      EXPECT_NEAR(mp.velocity_gradient(0, 1), expected, 0.04 * expected) << "h = " << h;
    }
  }
}

// As in column_test.cpp (σ_yy = -ρ g (H - y), σ_xx = 0 with ν = 0, checked as close to the floor and the
// top), but under the product's default transfer, which damps grid-scale motion far less than pure
// PIC, and with ℓ = 4 h.
TEST(NonlocalAverage, AnElasticColumnSettlesToTheGeostaticStress) {
  using Column = testing::SelfWeightColumn;
  const double length = 4 * Column::h;
  SolverSettings settings = testing::settings_with(VelocityTransfer{});
  settings.regularization.emplace(length);
  const Column column(settings, 1.5);
  const double scale = Column::rho * Column::g * Column::height;
  int checked = 0;
  for (const MaterialPoint& mp : column.solver.points()) {
    ASSERT_TRUE(mp.position.allFinite());
    const double y = column.initial_height_above_floor(mp);
    EXPECT_LT(mp.velocity.norm(), 1e-2) << "point at y = " << y;
    if (y < 3 * Column::h || y > Column::height - 2 * Column::h) continue;
    EXPECT_NEAR(mp.stress.in_plane(1, 1), -Column::rho * Column::g * (Column::height - y), 0.03 * scale)
        << "point at y = " << y;
    EXPECT_NEAR(mp.stress.in_plane(0, 0), 0.0, 0.03 * scale) << "point at y = " << y;
    ++checked;
  }
  EXPECT_GT(checked, 400);
}

}  // namespace
}  // namespace grainbank::mpm
