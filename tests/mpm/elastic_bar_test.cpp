// First longitudinal mode of a free-free elastic bar (ν = 0, so the 1D wave speed is c = sqrt(E/ρ)):
// v(x, t) = v0 cos(π x / L) cos(ω t) with ω = π c / L. The period, read from the zero crossings of
// the left half's momentum, converges to the analytic one as the grid is refined.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "mpm_test_util.hpp"

namespace grainbank::mpm {
namespace {

constexpr double kLength = 1.0, kYoung = 100.0, kDensity = 1.0;

// Relative error of the measured period for `cells` cells along the bar.
double period_error(int cells) {
  const double h = kLength / cells, x0 = 2 * h;
  Solver solver = testing::elastic_solver(Grid(Vec2(0, 0), h, cells + 4, 6), kDensity, kYoung, 0.0, 1.0);
  // 2 × 2 points per cell over 2 cells of height, the mode shape as initial velocity.
  const double spacing = h / 2;
  std::vector<bool> left;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 2 * cells; ++i) {
      const double xi = (i + 0.5) * spacing / kLength;
      solver.add_point(0, Vec2(x0 + xi * kLength, 2 * h + (j + 0.5) * spacing), spacing * spacing, spacing / 2,
                       Vec2(1e-3 * std::cos(std::numbers::pi * xi), 0));
      left.push_back(xi < 0.5);
    }
  const double c = std::sqrt(kYoung / kDensity), period = 2 * kLength / c;
  std::vector<double> crossings;
  double previous = 1, previous_t = 0;
  testing::run_until(solver, 3.2 * period, [&](const Solver& s) {
    double p = 0;
    for (const MaterialPoint& mp : s.points())
      if (left[mp.id]) p += mp.mass * mp.velocity.x();
    if ((p > 0) != (previous > 0)) crossings.push_back(previous_t + (s.time() - previous_t) * previous / (previous - p));
    previous = p;
    previous_t = s.time();
  });
  EXPECT_GE(crossings.size(), 6u);
  const double measured = 2 * (crossings.back() - crossings.front()) / double(crossings.size() - 1);
  return std::abs(measured - period) / period;
}

TEST(ElasticBar, FrequencyConvergesWithGridRefinement) {
  const double coarse = period_error(8), medium = period_error(16), fine = period_error(32);
  std::printf("period error: 8 cells %.4f%%, 16 cells %.4f%%, 32 cells %.4f%%\n", 100 * coarse, 100 * medium,
              100 * fine);
  EXPECT_LT(fine, 0.01);
  EXPECT_LT(medium, coarse);
  EXPECT_LT(fine, medium);
}

}  // namespace
}  // namespace grainbank::mpm
