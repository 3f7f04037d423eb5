// How an obstacle's contact meets the grid (transfers.hpp, ContactSpread): as the points' quadrature
// spreads the stress that carries the force into the body. Checked against weights worked out by hand
// from -V/A Σ_k ∂N_i/∂y over a column of points, and against the property they exist for: a column of
// points under a uniform stress, standing on the contact, is in equilibrium at every node its lowest
// points reach.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "mpm_solver/core/bspline.hpp"
#include "mpm_solver/core/transfers.hpp"

namespace grainbank::mpm {
namespace {

constexpr double kCell = 0.1;

// ∇N of the node at offset r = x - x_node.
Vec2 shape_gradient(const Vec2& r) {
  const SplineValue x = cubic_bspline(r.x() / kCell), y = cubic_bspline(r.y() / kCell);
  return Vec2(x.slope * y.value, x.value * y.slope) / kCell;
}

// Σ over the stencil's columns of the weights of its row b: the share of the force each row of nodes takes.
double row_share(const ContactSpread& spread, int b) {
  return spread.weight[b][0] + spread.weight[b][1] + spread.weight[b][2] + spread.weight[b][3];
}

TEST(ContactSpread, AFloorOnANodeLineSplitsTheForceAsThePointsQuadratureDoes) {
  const Grid grid(Vec2(0, 0), kCell, 8, 8);
  const double floor = 2 * kCell;
  // One point per cell (spacing h, centres h/2, 3h/2, … above the floor): ω_i = -Σ_k N'(u_k), u_k the
  // points' distances above node i in cells, N'(u) = 3u²/2 - 2u below 1 and -(2 - u)²/2 from 1 to 2,
  // gives 1/8, 3/4, 1/8 and 0 for the nodes at -h, 0, h and 2h from the floor.
  const ContactSpread one = contact_spread(grid, Vec2(0.43, floor + kCell / 2), Vec2(0, 1), kCell);
  const double expected_one[4] = {1.0 / 8, 3.0 / 4, 1.0 / 8, 0};
  // Two per cell (spacing h/2, centres h/4, 3h/4, …; ω_i = -Σ_k N'(u_k) / 2): 5/32, 11/16, 5/32 and 0,
  // where the shape functions at the floor give 1/6, 2/3, 1/6 and 0.
  const ContactSpread two = contact_spread(grid, Vec2(0.43, floor + kCell / 4), Vec2(0, 1), kCell / 2);
  const double expected_two[4] = {5.0 / 32, 11.0 / 16, 5.0 / 32, 0};
  for (int b = 0; b < 4; ++b) {
    EXPECT_NEAR(row_share(one, b), expected_one[b], 1e-12) << "row " << b;
    EXPECT_NEAR(row_share(two, b), expected_two[b], 1e-12) << "row " << b;
  }
}

// Net force at each node of the stencil of the lowest point from a column of points (spacing d along
// n, stress σ = -s n⊗n, s > 0, points' volume d², thickness d across) on a contact pushing with s d.
double worst_imbalance(const Grid& grid, const Vec2& lowest, const Vec2& n, double d, double s) {
  const ContactSpread spread = contact_spread(grid, lowest, n, d);
  const Stencil base = stencil_at(grid, lowest);
  double worst = 0;
  for (int b = 0; b < 4; ++b)
    for (int a = 0; a < 4; ++a) {
      const Vec2 node = lowest + Vec2(base.dx[a], base.dy[b]);
      Vec2 force = spread.weight[b][a] * (s * d) * n;
      for (int k = 0; k < 100; ++k)  // -V σ ∇N = V s n (n·∇N)
        force += d * d * s * n * n.dot(shape_gradient(lowest + k * d * n - node));
      worst = std::max(worst, force.norm());
    }
  return worst / (s * d);
}

TEST(ContactSpread, AColumnUnderUniformStressBalancesAtEveryNodeItsLowestPointsReach) {
  const Grid grid(Vec2(0, 0), kCell, 20, 20);
  for (const double d : {kCell, kCell / 2, kCell / 3}) {
    // On a node line the column's own quadrature is symmetric about every node it covers: exact.
    EXPECT_LT(worst_imbalance(grid, Vec2(0.43, 0.5 + d / 2), Vec2(0, 1), d, 1e3), 1e-12) << "d = " << d;
    // Off the grid's lines, and slanted, the weights are normalized to the whole force, and the
    // column's quadrature is the midpoint rule for a cubic: a small residue.
    for (const double angle : {0.0, 20.0, 45.0}) {
      const double t = angle * std::numbers::pi / 180;
      const Vec2 n(-std::sin(t), std::cos(t));
      const double imbalance = worst_imbalance(grid, Vec2(0.437, 0.513), n, d, 1e3);
      std::printf("d = h/%.0f, normal at %2.0f°: worst nodal imbalance %.2g of the force\n", kCell / d, angle, imbalance);
      EXPECT_LT(imbalance, 0.01) << "d = " << d << ", normal at " << angle << "°";
    }
  }
}

TEST(ContactSpread, WeightsSumToOneSoTheForceIsAppliedInFull) {
  const Grid grid(Vec2(0, 0), kCell, 20, 20);
  for (const double d : {kCell, kCell / 2, kCell / 3})
    for (const double angle : {0.0, 33.0, 90.0, 180.0, 251.0}) {
      const double t = angle * std::numbers::pi / 180;
      const ContactSpread spread = contact_spread(grid, Vec2(1.0137, 0.9821), Vec2(std::cos(t), std::sin(t)), d);
      double total = 0;
      for (int b = 0; b < 4; ++b) total += row_share(spread, b);
      EXPECT_NEAR(total, 1.0, 1e-12) << "d = " << d << ", normal at " << angle << "°";
    }
}

}  // namespace
}  // namespace grainbank::mpm
