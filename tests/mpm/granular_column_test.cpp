// The cohesionless column collapse against the planar experiments of Lube et al. (2005), and its
// independence of the time step: if nothing but the material and the base dissipates, halving Δt
// must not change the runout (the per-step FLIP/PIC blend made it a numerical viscosity).
#include <gtest/gtest.h>

#include <cstdio>

#include "tests/mpm/granular_column.hpp"

namespace grainbank::mpm {
namespace {

// With APIC, not the default: its per-step damping is part of this agreement. The default APIC-FLIP
// (5 PIC per second) runs out 1.78 here (48 % beyond Lube) and 1.39 at L0/h = 10: not converged in h,
// so issue 17's validation against Lube is still open.
TEST(GranularColumn, ApicRunoutAtAspectRatioOneIsLubesWithinThirtyPercent) {
  testing::ColumnSetup apic;
  apic.transfer = testing::apic();
  const testing::ColumnResult r = testing::collapse(apic);
  std::printf("a = 1, L0 = 0.2 m, h = 0.01 m: runout %.3f (Lube %.2f), H_inf/H0 %.3f, at rest at t = %.3f s after %ld steps\n",
              r.runout, testing::lube_runout(1), r.final_height, r.rest_time, r.steps);
  EXPECT_NEAR(r.runout, testing::lube_runout(1), 0.3 * testing::lube_runout(1));
}

// Issue 17's requirement: only the material and the base dissipate, so halving Δt does not change
// the runout. APIC alone fails it (its projection onto affine point velocities dissipates at every
// transfer: 1.153 at CFL 0.5 against 1.004 at 0.25 for L0/h = 20); the default APIC-FLIP damps at a
// rate per second, not per step.
TEST(GranularColumn, RunoutDoesNotDependOnTheTimeStep) {
  // On a coarser grid (L0 / h = 10) to keep it short.
  testing::ColumnSetup coarse, fine;
  coarse.cell_size = fine.cell_size = 0.02;
  coarse.step_factor = 0.5;
  fine.step_factor = 0.25;
  const testing::ColumnResult a = testing::collapse(coarse), b = testing::collapse(fine);
  std::printf("runout at CFL 0.5: %.4f (%ld steps), at CFL 0.25: %.4f (%ld steps)\n", a.runout, a.steps, b.runout,
              b.steps);
  EXPECT_NEAR(a.runout, b.runout, 0.02 * b.runout);
}

}  // namespace
}  // namespace grainbank::mpm
