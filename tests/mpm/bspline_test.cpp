// Cubic B-spline stencils: partition of unity and zero gradient sum everywhere in the grid,
// including the first and last cell (the ghost ring), agreement with the closed-form spline, and
// APIC's D_p = h²/3 I there too.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "mpm_solver/core/bspline.hpp"

namespace grainbank::mpm {
namespace {

double cubic_bspline(double d) {
  d = std::abs(d);
  if (d < 1) return 0.5 * d * d * d - d * d + 2.0 / 3;
  if (d < 2) return (2 - d) * (2 - d) * (2 - d) / 6;
  return 0;
}

TEST(BSpline, PartitionOfUnityAndZeroGradientSumUpToTheBorder) {
  const Grid grid(Vec2(-0.3, 0.2), 0.1, 5, 4);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ux(-0.3, 0.2 - 1e-12), uy(0.2, 0.6 - 1e-12);
  std::vector<Vec2> samples = {grid.lower(), Vec2(0.2 - 1e-9, 0.6 - 1e-9), Vec2(-0.3, 0.55), Vec2(0.199, 0.2)};
  for (int k = 0; k < 200; ++k) samples.emplace_back(ux(rng), uy(rng));
  for (const Vec2& x : samples) {
    ASSERT_TRUE(grid.contains(x));
    const Stencil s = stencil_at(grid, x);
    double sum = 0;
    Vec2 grad_sum = Vec2::Zero(), first_moment = Vec2::Zero();
    Mat2 second_moment = Mat2::Zero();
    for (int b = 0; b < 4; ++b)
      for (int a = 0; a < 4; ++a) {
        const std::size_t node = s.first_node + a + b * grid.nodes_x();
        ASSERT_LT(node, grid.node_count());
        const Vec2 xn = grid.lower() + grid.cell_size() * Vec2(double(node % grid.nodes_x()) - 1,
                                                                double(node / grid.nodes_x()) - 1);
        const double N = s.wx[a] * s.wy[b];
        EXPECT_NEAR(N, cubic_bspline((x.x() - xn.x()) / 0.1) * cubic_bspline((x.y() - xn.y()) / 0.1), 1e-14);
        sum += N;
        grad_sum += Vec2(s.gx[a] * s.wy[b], s.wx[a] * s.gy[b]);
        first_moment += N * xn;
        const Vec2 d(s.dx[a], s.dy[b]);
        EXPECT_NEAR((d - (xn - x)).norm(), 0.0, 1e-14);
        second_moment += N * d * d.transpose();
      }
    EXPECT_NEAR(sum, 1.0, 1e-14);
    EXPECT_NEAR(grad_sum.norm(), 0.0, 1e-12);
    // Cubic B-splines also reproduce linear fields: Σ N x_i = x.
    EXPECT_NEAR((first_moment - x).norm(), 0.0, 1e-14);
    // and quadratic ones up to h²/3: D_p is the same constant for every point, border cells included.
    EXPECT_NEAR((second_moment - affine_inertia(0.1) * Mat2::Identity()).norm(), 0.0, 1e-15);
  }
}

}  // namespace
}  // namespace grainbank::mpm
