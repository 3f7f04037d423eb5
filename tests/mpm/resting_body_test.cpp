// Bodies at rest on a frictional base stay at rest under the default APIC-FLIP transfer and under
// pure APIC-FLIP (no PIC at all). Nothing does work on a resting body once its load is in, so its
// energy cannot grow, and a Coulomb material below its friction angle does not flow. Until stop 48
// the obstacle contact took the point's own velocity, whose FLIP fluctuations the grid does not
// carry: the tangential spring and the dashpot then did work that no displacement paid for (an
// elastic heap's kinetic energy grew 25–50-fold after its load was in, and a 25° heap of 30° sand
// crept 0.31 mm in 0.6 s).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "mpm_solver/core/diagnostics.hpp"
#include "mpm_solver/laws/drucker_prager_law.hpp"
#include "tests/mpm/mpm_test_util.hpp"

namespace grainbank::mpm {
namespace {

constexpr double kDensity = 1500, kYoung = 5e6, kPoisson = 0.3, kCell = 0.01, kBase = 0.02;
constexpr double kRampEnd = 0.1;

// A triangular heap (base 0.4 m, slopes at `slope_deg`) of `law` on a rough base (friction 1), as stiff
// as the material over one cell, gravity ramped in over 0.1 s.
Solver heap(std::unique_ptr<ConstitutiveLaw> law, double slope_deg, const VelocityTransfer& transfer) {
  const double half = 0.2, height = half * std::tan(slope_deg * std::numbers::pi / 180);
  Solver solver(Grid(Vec2(0, 0), kCell, 100, static_cast<int>((kBase + height) / kCell) + 4),
                testing::settings_with(transfer));
  solver.add_law(std::move(law));
  seed_region(solver, 0, Polyline{{Vec2(0.5 - half, kBase), Vec2(0.5 + half, kBase), Vec2(0.5, kBase + height)}, true},
              2);
  const double k = Elasticity{kYoung, kPoisson}.p_wave_modulus() / 4;
  solver.add_obstacle(Obstacle(Polyline{{Vec2(-1, kBase), Vec2(2, kBase)}, false}, ContactParameters{k, k, 1.0, 0.5}));
  solver.set_gravity(Gravity{Vec2(0, -9.81), GravityRamp{Vec2::Zero(), 0, kRampEnd}});
  return solver;
}

double top(const Solver& solver) { return measure_flow(solver.points()).max_height; }

TEST(RestingBody, AnElasticHeapOnAFrictionalBaseGainsNoEnergy) {
  for (const VelocityTransfer& transfer : {VelocityTransfer{}, testing::apic_flip(0)}) {
    Solver solver = heap(std::make_unique<ElasticLaw>(kDensity, Elasticity{kYoung, kPoisson}), 20, transfer);
    double loaded = 0, late = 0;  // largest kinetic energy just after the load is in, and late
    testing::run_until(solver, 0.8, [&](const Solver& s) {
      const double e = measure_flow(s.points()).kinetic_energy;
      if (s.time() >= kRampEnd && s.time() < kRampEnd + 0.1) loaded = std::max(loaded, e);
      if (s.time() >= 0.6) late = std::max(late, e);
    });
    std::printf("%s: kinetic energy %.3g J/m after loading, %.3g J/m at 0.6-0.8 s\n", testing::describe(transfer).c_str(),
                loaded, late);
    EXPECT_GT(loaded, 0);
    // Without PIC nothing dissipates, and the kinetic share of the body's ringing beats between
    // windows; growth is what the test rejects (it was 25–50-fold). Sampled every 0.05 s, the heap's
    // kinetic energy without PIC rises to 1.8× (stop 76's contact) and 2.1× (stop 77's) its level at
    // 0.2 s by 0.5 s, and stays there to 0.8 s.
    EXPECT_LE(late, 3 * loaded) << testing::describe(transfer);
  }
}

TEST(RestingBody, ADruckerPragerHeapBelowItsFrictionAngleStands) {
  // φ = 30°, slopes 25°: statically admissible, so the apex only settles elastically, by about
  // ρ g H² / (2E) = 0.013 mm.
  const DruckerPragerParameters sand{Elasticity{kYoung, kPoisson}, 30 * std::numbers::pi / 180, 0, 0, std::nullopt};
  Solver solver = heap(std::make_unique<DruckerPragerLaw>(kDensity, sand), 25, VelocityTransfer{});
  const double before = top(solver);
  testing::run_until(solver, 0.6);
  const double settled = before - top(solver);
  std::printf("apex settled by %.4f mm\n", 1e3 * settled);
  EXPECT_LT(settled, 0.03e-3);
  EXPECT_LT(measure_flow(solver.points()).kinetic_energy, 1e-6);
}

}  // namespace
}  // namespace grainbank::mpm
