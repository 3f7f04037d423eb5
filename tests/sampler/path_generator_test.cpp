// The path generator: deterministic, covers the requested rate range and all of strain-rate space,
// honours the strain budget, and changes direction as asked.
#include <gtest/gtest.h>

#include <cmath>

#include "dem_sampler/sampler/halton.hpp"
#include "dem_sampler/sampler/path_generator.hpp"

namespace grainbank::sampler {
namespace {

GeneratorSpec spec(long count) {
  GeneratorSpec g;
  g.count = count;
  g.min_rate = 0.1;
  g.max_rate = 10;
  g.strain = 0.02;
  g.segments = 3;
  g.record_interval = 1e-3;
  return g;
}

double rate_of(const dem::Mat3& L) { return (0.5 * (L + L.transpose())).norm(); }

TEST(Halton, IsTheRadicalInverse) {
  EXPECT_DOUBLE_EQ(halton(1, 0), 0.5);
  EXPECT_DOUBLE_EQ(halton(3, 0), 0.75);
  EXPECT_DOUBLE_EQ(halton(1, 1), 1.0 / 3);
  EXPECT_DOUBLE_EQ(halton(5, 1), 2.0 / 3 + 1.0 / 9);  // 5 = 12 in base 3
}

TEST(PathGenerator, IsDeterministic) {
  const auto a = generate_paths(spec(16)), b = generate_paths(spec(16));
  ASSERT_EQ(a.size(), 16u);
  for (std::size_t k = 0; k < a.size(); ++k) EXPECT_EQ(to_json(a[k]).dump(), to_json(b[k]).dump());
  // A later start continues the same sequence.
  GeneratorSpec tail = spec(8);
  tail.start = 8;
  const auto c = generate_paths(tail);
  for (std::size_t k = 0; k < c.size(); ++k) EXPECT_EQ(to_json(c[k]).dump(), to_json(a[k + 8]).dump());
}

TEST(PathGenerator, CoversTheRateRangeLogUniformly) {
  const auto paths = generate_paths(spec(64));
  double low = 1e300, high = 0;
  int below_one = 0;
  for (const PathPlan& p : paths) {
    const double r = rate_of(p.path.segments[0].L);
    EXPECT_GE(r, 0.1 * (1 - 1e-12));
    EXPECT_LE(r, 10 * (1 + 1e-12));
    low = std::min(low, r), high = std::max(high, r);
    below_one += r < 1;
  }
  EXPECT_LT(low, 0.1 * 1.2);
  EXPECT_GT(high, 10 / 1.2);
  EXPECT_NEAR(below_one, 32, 3);  // 1 /s is the log-midpoint of [0.1, 10]
}

TEST(PathGenerator, CoversEveryOctantOfStrainRateSpace) {
  int octants[8] = {};
  for (const PathPlan& p : generate_paths(spec(64))) {
    const dem::Mat3& L = p.path.segments[0].L;
    const double vol = L(0, 0) + L(1, 1), dev = L(0, 0) - L(1, 1), shear = L(0, 1) + L(1, 0);
    ++octants[(vol > 0) + 2 * (dev > 0) + 4 * (shear > 0)];
    EXPECT_EQ(L(2, 2), 0);
    EXPECT_EQ(L(0, 2), 0);
  }
  for (int count : octants) EXPECT_GE(count, 4);
}

TEST(PathGenerator, SpendsTheStrainBudgetAndChangesDirection) {
  GeneratorSpec g = spec(10);
  g.changes = {DirectionChange::reversal, DirectionChange::rotation};
  for (const PathPlan& p : generate_paths(g)) {
    ASSERT_EQ(p.path.segments.size(), 3u);
    double strain = 0;
    for (const auto& s : p.path.segments) strain += rate_of(s.L) * s.duration;
    EXPECT_NEAR(strain, 0.02, 1e-12);
    EXPECT_TRUE(p.path.segments[1].L.isApprox(-p.path.segments[0].L));
    const dem::Mat3 D1 = 0.5 * (p.path.segments[1].L + p.path.segments[1].L.transpose());
    const dem::Mat3 D2 = 0.5 * (p.path.segments[2].L + p.path.segments[2].L.transpose());
    EXPECT_NEAR(D2.norm(), D1.norm(), 1e-12 * D1.norm());      // same rate
    EXPECT_NEAR(D2.trace(), D1.trace(), 1e-12 * D1.norm());    // same volumetric part
    EXPECT_FALSE(D2.isApprox(D1, 1e-3));                       // principal axes turned
  }
}

TEST(PathGenerator, SpinAndVolumetricWeightAreBounded) {
  GeneratorSpec g = spec(32);
  g.spin = 0.5;
  g.volumetric = 0;
  for (const PathPlan& p : generate_paths(g)) {
    const dem::Mat3& L = p.path.segments[0].L;
    EXPECT_NEAR(L(0, 0) + L(1, 1), 0, 1e-12);
    const double w = std::abs(L(0, 1) - L(1, 0)) / 2 * std::sqrt(2.0);
    EXPECT_LE(w, 0.5 * rate_of(L) * (1 + 1e-12));
  }
}

TEST(PathGenerator, RejectsAnInconsistentSpec) {
  GeneratorSpec g = spec(4);
  g.min_rate = 2, g.max_rate = 1;
  EXPECT_THROW(generate_paths(g), std::invalid_argument);
}

}  // namespace
}  // namespace grainbank::sampler
