// The cache law on a library that holds the exact path of a homogeneously deformed point: every
// lookup hits and returns the live stress within the lookup's interpolation error (zero on the
// path itself, so: round-off).
#include <gtest/gtest.h>

#include <vector>

#include "tests/mpm/coupling_test_util.hpp"

namespace grainbank::mpm {
namespace {

using namespace testing;

TEST(CacheLaw, ReproducesTheLiveStressOfAPathTheLibraryHolds) {
  const auto dir = fresh_library_dir();
  const std::int64_t id = create_library(dir, small_snow_cell());
  // Simple shear with compression, then a turn: small enough strains that no bond breaks.
  const double dt = 2e-4;
  std::vector<Mat2> increments;
  for (int k = 0; k < 24; ++k) {
    Mat2 L;
    if (k < 12) L << -0.3, 1.0, 0.0, -0.2;
    else L << 0.2, -0.5, 0.6, -0.4;
    increments.push_back(Mat2::Identity() + dt * L);
  }
  // The exact path: one point of a hybrid law on the empty library turns live at once, and its live
  // responses become the library's only path (enrichment writes them through ShardWriter).
  std::vector<PointStress> live;
  {
    auto hybrid = library_law(dir, id, coupling_settings(Fallback::warm_start, true));
    PointStress s;
    hybrid->add_point(s);
    PointDriver drive;
    for (const Mat2& inc : increments) {
      drive(*hybrid, inc, dt, s);
      live.push_back(s);
    }
    hybrid->finish();
    EXPECT_EQ(hybrid->counters().enriched_records, increments.size());
  }
  auto cache = library_law(dir, id, coupling_settings(Fallback::none, false));
  EXPECT_EQ(cache->link().index().size(), increments.size());
  PointStress s;
  cache->add_point(s);
  PointDriver drive;
  for (std::size_t k = 0; k < increments.size(); ++k) {
    drive(*cache, increments[k], dt, s);
    const double scale = std::abs(live[k].in_plane.trace());
    EXPECT_EQ(cache->source(0), StressSource::hit) << "increment " << k;
    EXPECT_LE((s.in_plane - live[k].in_plane).norm(), cache->estimated_error(0) + 1e-9 * scale) << "increment " << k;
    EXPECT_NEAR(s.zz, live[k].zz, cache->estimated_error(0) + 1e-9 * scale);
  }
  const CouplingCounters c = cache->counters();
  EXPECT_EQ(c.hits, increments.size());
  EXPECT_EQ(c.misses, 0u);
  EXPECT_EQ(c.went_live, 0u);
}

TEST(CacheLaw, AnEmptyLibraryIsRefusedWithTheRemedy) {
  const auto dir = fresh_library_dir();
  const std::int64_t id = create_library(dir, small_snow_cell());  // a template, no path
  try {
    library_law(dir, id, coupling_settings(Fallback::none, false));
    FAIL() << "expected a refusal";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("use hybrid or sample paths"), std::string::npos) << e.what();
  }
}

TEST(CacheLaw, AMissIsAnsweredByTheNearestStateAndCounted) {
  const auto dir = fresh_library_dir();
  const std::int64_t id = create_library(dir, small_snow_cell());
  {
    auto hybrid = library_law(dir, id, coupling_settings(Fallback::warm_start, true));
    PointStress s;
    hybrid->add_point(s);
    PointDriver drive;
    for (int k = 0; k < 4; ++k) drive(*hybrid, Mat2::Identity() + 2e-4 * Mat2{{0, 1}, {0, 0}}, 2e-4, s);
    hybrid->finish();
  }
  auto cache = library_law(dir, id, coupling_settings(Fallback::none, false));
  PointStress s;
  cache->add_point(s);
  // A large compression: far from the stored shear path.
  PointDriver{}(*cache, Mat2::Identity() + 0.05 * Mat2{{-1, 0}, {0, -1}}, 2e-4, s);
  EXPECT_EQ(cache->source(0), StressSource::miss);
  EXPECT_EQ(cache->counters().misses, 1u);
  EXPECT_GT(s.in_plane.norm(), 0);  // still answered
  EXPECT_EQ(cache->live_cell(0), nullptr);
}

}  // namespace
}  // namespace grainbank::mpm
