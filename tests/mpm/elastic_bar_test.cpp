// First longitudinal mode of a free-free elastic bar (ν = 0, so the 1D wave speed is c = sqrt(E/ρ)):
// v(x, t) = v0 cos(π x / L) cos(ω t) with ω = π c / L. The period, read from the zero crossings of
// the left half's momentum, converges to the analytic one as the grid is refined; its amplitude, the
// peak momentum between crossings, is kept (the material is elastic: only the transfer could damp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "tests/mpm/mpm_test_util.hpp"

namespace grainbank::mpm {
namespace {

constexpr double kLength = 1.0, kYoung = 100.0, kDensity = 1.0;

struct Vibration {
  double period_error;      // relative to the analytic period
  double decay_per_period;  // relative loss of amplitude per period
};

Vibration vibration(int cells) {
  const double h = kLength / cells, x0 = 2 * h;
  Solver solver = testing::elastic_solver(Grid(Vec2(0, 0), h, cells + 4, 6), kDensity, kYoung, 0.0);
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
  std::vector<double> crossings, peaks{0};
  double previous = 1, previous_t = 0;
  testing::run_until(solver, 3.2 * period, [&](const Solver& s) {
    double p = 0;
    for (const MaterialPoint& mp : s.points())
      if (left[mp.id]) p += mp.mass * mp.velocity.x();
    if ((p > 0) != (previous > 0)) {
      crossings.push_back(previous_t + (s.time() - previous_t) * previous / (previous - p));
      peaks.push_back(0);
    }
    peaks.back() = std::max(peaks.back(), std::abs(p));
    previous = p;
    previous_t = s.time();
  });
  EXPECT_GE(crossings.size(), 6u);
  const double measured = 2 * (crossings.back() - crossings.front()) / double(crossings.size() - 1);
  // Whole half-periods lie between the first and the last crossing: peaks[1] … peaks[n - 1].
  const double half_periods = double(crossings.size() - 2);
  const double decay = 1 - std::pow(peaks[crossings.size() - 1] / peaks[1], 2 / half_periods);
  return {std::abs(measured - period) / period, decay};
}

TEST(ElasticBar, FrequencyConvergesWithGridRefinement) {
  const double coarse = vibration(8).period_error, medium = vibration(16).period_error,
               fine = vibration(32).period_error;
  std::printf("period error: 8 cells %.4f%%, 16 cells %.4f%%, 32 cells %.4f%%\n", 100 * coarse, 100 * medium,
              100 * fine);
  EXPECT_LT(fine, 0.01);
  EXPECT_LT(medium, coarse);
  EXPECT_LT(fine, medium);
}

TEST(ElasticBar, AmplitudeDecaysLessThanOnePercentPerPeriod) {
  // (APIC filters what its affine fields cannot carry: on 8 cells per half wavelength the mode
  // loses about 3 % per period, falling as h³.)
  for (int cells : {16, 32}) {
    const Vibration v = vibration(cells);
    std::printf("%d cells: amplitude decay per period %.3f%%\n", cells, 100 * v.decay_per_period);
    EXPECT_LT(std::abs(v.decay_per_period), 0.01) << cells << " cells";
  }
}

}  // namespace
}  // namespace grainbank::mpm
