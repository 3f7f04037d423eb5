// Progress lines' ETA from the recent pace (common/recent_pace_eta.hpp): a run whose cost per unit of
// progress rises half-way (a surrogate column once its gate opens) is given the ETA of its present
// pace, not of its cheap beginning. Samples carry explicit wall times: nothing here is timed.
#include "common/recent_pace_eta.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace grainbank {
namespace {

using common::RecentPaceEta;

TEST(RecentPaceEta, FollowsARunThatSlowsDownWithinOneWindow) {
  RecentPaceEta eta(60);
  // Half the run in 10 s, then a thousandth per second, sampled every second.
  for (int s = 0; s <= 10; ++s) eta.record(s, 0.05 * s);
  for (int s = 11; s <= 110; ++s) eta.record(s, 0.5 + 0.001 * (s - 10));
  // 0.4 left at 0.001 per second; the average since the start (0.6 in 110 s) would say 73 s.
  EXPECT_NEAR(eta.eta(), 400, 1e-6);
}

TEST(RecentPaceEta, IsTheAverageSinceTheFirstSampleWithinTheFirstWindow) {
  RecentPaceEta eta(60);
  // A resumed run: its first sample is where it resumed, 30 % done.
  eta.record(100, 0.3);
  eta.record(105, 0.32);
  eta.record(110, 0.4);
  EXPECT_NEAR(eta.eta(), 0.6 / (0.1 / 10), 1e-9);
}

TEST(RecentPaceEta, IsUnknownWithoutTwoSamplesOrWithoutProgress) {
  RecentPaceEta eta(60);
  EXPECT_TRUE(std::isnan(eta.eta()));
  eta.record(0, 0.2);
  EXPECT_TRUE(std::isnan(eta.eta()));
  eta.record(0, 0.3);  // no wall time between them
  EXPECT_TRUE(std::isnan(eta.eta()));
  // Progress before the window, none within it: a stalled run has no ETA.
  RecentPaceEta stalled(2);
  stalled.record(0, 0.0);
  stalled.record(1, 0.1);
  stalled.record(10, 0.1);
  stalled.record(11, 0.1);
  EXPECT_TRUE(std::isnan(stalled.eta()));
}

TEST(RecentPaceEta, RefusesAWindowThatIsNotPositive) {
  EXPECT_THROW(RecentPaceEta(0), std::invalid_argument);
  EXPECT_THROW(RecentPaceEta(std::nan("")), std::invalid_argument);
}

}  // namespace
}  // namespace grainbank
