// Progress lines' ETA (common/duration_text.hpp): readable units, and "unknown" where there is
// nothing to extrapolate from or the run would not end (a progress line once printed "ETA inf s").
#include "common/duration_text.hpp"

#include <gtest/gtest.h>

#include <limits>

namespace grainbank {
namespace {

using common::duration_text;

TEST(DurationText, ReadsInSecondsMinutesOrHours) {
  EXPECT_EQ(duration_text(0), "0 s");
  EXPECT_EQ(duration_text(41.6), "42 s");
  EXPECT_EQ(duration_text(185), "3 min 5 s");
  EXPECT_EQ(duration_text(2 * 3600 + 10 * 60 + 29), "2 h 10 min");
}

TEST(DurationText, IsUnknownWhenNotFiniteNegativeOrBeyondTenThousandHours) {
  EXPECT_EQ(duration_text(std::numeric_limits<double>::infinity()), "unknown");
  EXPECT_EQ(duration_text(std::numeric_limits<double>::quiet_NaN()), "unknown");
  EXPECT_EQ(duration_text(-1), "unknown");
  EXPECT_EQ(duration_text(1e300), "unknown");
  EXPECT_EQ(duration_text(9999.0 * 3600), "9999 h 0 min");
}

}  // namespace
}  // namespace grainbank
