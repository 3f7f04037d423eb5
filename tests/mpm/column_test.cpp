// An elastic column (ν = 0, free sides) resting on a frictionless floor under its own weight: once the
// transient is damped out (gravity ramped up), σ_yy = -ρ g (H - y) and σ_xx = 0, where y is the
// initial height of the point above the base (mass per area above it is conserved). Every point is
// checked, the rows at the floor and the top too, at one, two and three points per cell, under pure
// APIC and under the product's default APIC-FLIP blend.
//
// At more than one point per cell the nodes' equilibrium does not fix the points' stresses (more
// points than nodes), so the rows at the floor carry what the floor's reaction asks of them. Spread
// from the points' centres, it loaded the five rows within 3 h of the floor wrongly by more than the
// tolerance (stop 76); spread with the shape functions of the touching point, the lowest two rows at
// two points per cell settled at 109 % and 87 % of their overburden (stop 77). The contact is now
// spread as the points' quadrature spreads the stress that carries it (transfers.hpp, ContactSpread).
// Pure PIC is not tested: it does not carry an affine velocity field to the nodes below the floor,
// which only the lowest points reach, and its column settles with its lowest rows 3 % off.
#include <gtest/gtest.h>

#include "tests/mpm/mpm_test_util.hpp"

namespace grainbank::mpm {
namespace {

TEST(ElasticColumn, SelfWeightStressProfile) {
  using Column = testing::SelfWeightColumn;
  const double scale = Column::rho * Column::g * Column::height;
  for (const VelocityTransfer& transfer : {testing::apic(), VelocityTransfer{}})
    for (int n : {1, 2, 3}) {
      const Column column(testing::settings_with(transfer), 1.5, n);
      int checked = 0;
      for (const MaterialPoint& mp : column.solver.points()) {
        const double y = column.initial_height_above_floor(mp);
        EXPECT_NEAR(mp.stress.in_plane(1, 1), -Column::rho * Column::g * (Column::height - y), 0.02 * scale)
            << testing::describe(transfer) << ", " << n << " points per cell, point at y = " << y;
        EXPECT_NEAR(mp.stress.in_plane(0, 0), 0.0, 0.02 * scale) << testing::describe(transfer) << ", " << n;
        EXPECT_NEAR(mp.velocity.norm(), 0.0, 1e-3) << testing::describe(transfer) << ", " << n;
        ++checked;
      }
      EXPECT_EQ(checked, 8 * n * 20 * n);  // the 0.4 m × 1 m column, cells of 0.05 m
    }
}

}  // namespace
}  // namespace grainbank::mpm
