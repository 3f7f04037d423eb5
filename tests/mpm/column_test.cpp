// An elastic column (ν = 0, free sides) resting on a frictionless floor under its own weight: once the
// transient is damped out (pure PIC, gravity ramped up), σ_yy = -ρ g (H - y) and σ_xx = 0, where y is
// the initial height of the point above the base (mass per area above it is conserved). Every point
// is checked, the rows at the floor and the top too: the floor's reaction acts where the points touch
// it (obstacle.hpp). Spread from the points' centres instead, it loaded the five rows within 3 h of
// the floor wrongly by more than the tolerance (stop 76).
#include <gtest/gtest.h>

#include "tests/mpm/mpm_test_util.hpp"

namespace grainbank::mpm {
namespace {

TEST(ElasticColumn, SelfWeightStressProfile) {
  using Column = testing::SelfWeightColumn;
  const Column column(testing::settings_with(testing::pure_pic()), 1.0);
  const double scale = Column::rho * Column::g * Column::height;
  int checked = 0;
  for (const MaterialPoint& mp : column.solver.points()) {
    const double y = column.initial_height_above_floor(mp);
    EXPECT_NEAR(mp.stress.in_plane(1, 1), -Column::rho * Column::g * (Column::height - y), 0.02 * scale)
        << "point at y = " << y;
    EXPECT_NEAR(mp.stress.in_plane(0, 0), 0.0, 0.02 * scale);
    EXPECT_NEAR(mp.velocity.norm(), 0.0, 1e-3);
    ++checked;
  }
  EXPECT_EQ(checked, 16 * 40);  // 2 × 2 points per cell of the 0.4 m × 1 m column
}

}  // namespace
}  // namespace grainbank::mpm
