// The velocity transfers against conservation laws: APIC keeps the angular momentum and the kinetic
// energy of a rigidly rotating disk (the per-step FLIP/PIC blend of earlier versions lost both), the
// blend's damping is a rate that does not change with Δt, and the MUSL position update neither gains
// nor loses energy on average when a point bounces on an undamped penalty obstacle; blending out the
// rough part of a point's fluctuation at a rate of its own moves no momentum and damps no resolved mode.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "mpm_solver/core/diagnostics.hpp"
#include "tests/mpm/mpm_test_util.hpp"

namespace grainbank::mpm {
namespace {

constexpr double kDensity = 1000, kYoung = 1e7, kPoisson = 0.3;

// Angular momentum about c, Σ m_p ((x_p − c) × v_p + B_p,yx − B_p,xy): the points' own plus the
// spin carried by APIC's affine velocity (Jiang et al. 2015, whose grid transfer conserves it).
double angular_momentum(const std::vector<MaterialPoint>& points, const Vec2& c) {
  double total = 0;
  for (const MaterialPoint& mp : points) {
    const Vec2 r = mp.position - c;
    const Mat2& B = mp.affine_velocity;
    total += mp.mass * (r.x() * mp.velocity.y() - r.y() * mp.velocity.x() + B(1, 0) - B(0, 1));
  }
  return total;
}

struct SpinLoss {
  double angular_momentum, kinetic_energy;  // relative change over the run
};

// An elastic disk (radius 0.25 m, 2 × 2 points per cell of 0.05 m) spinning rigidly at 2 rad/s,
// 1000 steps of 0.3 h / c_p. Under the affine transfers the points start with the affine part of
// the rigid motion, B_p = W D_p (W the spin), as a restart would restore it.
SpinLoss spinning_disk_loss(const VelocityTransfer& transfer, double* dt_out = nullptr) {
  const double h = 0.05, radius = 0.25, omega = 2;
  const Vec2 c(0.5, 0.5);
  Solver solver = testing::elastic_solver(Grid(Vec2(0, 0), h, 20, 20), kDensity, kYoung, kPoisson, transfer);
  const double spacing = h / 2;
  for (int j = 0; j < 40; ++j)
    for (int i = 0; i < 40; ++i) {
      const Vec2 x = Vec2(i + 0.5, j + 0.5) * spacing;
      const Vec2 r = x - c;
      if (r.norm() < radius) solver.add_point(0, x, spacing * spacing, spacing / 2, omega * Vec2(-r.y(), r.x()));
    }
  if (transfer.affine()) {
    std::vector<MaterialPoint> points = solver.points();
    Mat2 spin;
    spin << 0, -omega, omega, 0;
    for (MaterialPoint& mp : points) mp.affine_velocity = affine_inertia(h) * spin;
    solver.restore(0, 0, points);
  }
  const double dt = solver.stable_time_step();
  if (dt_out) *dt_out = dt;
  const double l0 = angular_momentum(solver.points(), c), k0 = measure_flow(solver.points()).kinetic_energy;
  for (int k = 0; k < 1000; ++k) solver.step(dt);
  return {angular_momentum(solver.points(), c) / l0 - 1, measure_flow(solver.points()).kinetic_energy / k0 - 1};
}

TEST(Transfer, AffineTransfersKeepTheAngularMomentumAndKineticEnergyOfASpinningDisk) {
  const SpinLoss apic = spinning_disk_loss(testing::apic()), apic_flip = spinning_disk_loss(testing::apic_flip(0));
  const SpinLoss standard = spinning_disk_loss(VelocityTransfer{});  // APIC-FLIP at its default rate
  // The earlier default: 5 % of PIC per step, i.e. a PIC rate −ln(0.95)/Δt.
  double dt = 0;
  spinning_disk_loss(testing::apic(), &dt);
  const SpinLoss blend = spinning_disk_loss(testing::flip_pic(-std::log(0.95) / dt));
  std::printf("1000 steps of a spinning disk: relative change of L and kinetic energy: APIC %.2e %.2e, "
              "APIC-FLIP at PIC rate 0 %.2e %.2e, default %.2e %.2e, blend 0.95 per step %.2e %.2e\n",
              apic.angular_momentum, apic.kinetic_energy, apic_flip.angular_momentum, apic_flip.kinetic_energy,
              standard.angular_momentum, standard.kinetic_energy,
              blend.angular_momentum, blend.kinetic_energy);
  EXPECT_NEAR(apic.angular_momentum, 0, 1e-10) << "APIC conserves angular momentum exactly";
  // The FLIP update keeps each point's departure from the interpolated grid velocity,
  // v_p − Σ N v_i, whose moment the grid does not see: not exact (−1.0e-5 over these 1000 steps), but
  // five orders below the per-step blend's loss.
  EXPECT_NEAR(apic_flip.angular_momentum, 0, 1e-4);
  EXPECT_NEAR(standard.angular_momentum, 0, 1e-4);
  // The disk's elastic energy (centrifugal stretch, ρ ω² R² / E ~ 4e-5) bounds the exchange.
  EXPECT_NEAR(apic.kinetic_energy, 0, 1e-3);
  EXPECT_NEAR(apic_flip.kinetic_energy, 0, 1e-3);
  EXPECT_NEAR(standard.kinetic_energy, 0, 1e-3);
  EXPECT_LT(blend.angular_momentum, -1e-2) << "the test must tell a dissipative transfer";
}

// The remaining kinetic energy of the vibrating bar after `duration`, stepped at a fixed dt,
// relative to the initial one.
double bar_energy_left(const VelocityTransfer& transfer, double dt, double duration) {
  Solver solver = testing::vibrating_bar(transfer);
  const double e0 = measure_flow(solver.points()).kinetic_energy;
  const int steps = static_cast<int>(std::lround(duration / dt));
  for (int k = 0; k < steps; ++k) solver.step(dt);
  return measure_flow(solver.points()).kinetic_energy / e0;
}

TEST(Transfer, BlendDampingIsARatePerSecondNotPerStep) {
  // After one period the bar's energy is all kinetic again. The share of it that a PIC rate of 20/s
  // removes beyond pure FLIP is the same at Δt and Δt / 2 (a fixed per-step fraction would remove
  // twice as much at Δt / 2).
  const double period = testing::kBarPeriod, dt = 2e-3;
  double loss[2];
  for (int k : {0, 1}) {
    const double step = dt / (1 + k);
    const double flip = bar_energy_left(testing::pure_flip(), step, period);
    const double blend = bar_energy_left(testing::flip_pic(20), step, period);
    loss[k] = 1 - blend / flip;
    std::printf("bar energy left after one period at dt %.3g: pure FLIP %.4f, PIC rate 20/s %.4f\n", step, flip, blend);
  }
  EXPECT_GT(loss[1], 0.1) << "the rate must damp";
  EXPECT_NEAR(loss[0], loss[1], 0.1 * loss[1]);
}

// A block of 2 × 2 points per cell moving at U, each point's velocity off it by ±δ in x, the sign
// alternating from point to point: a pattern the grid cannot resolve. The block's stiffness is
// negligible over one step, so only the transfer changes the velocities.
struct CheckerboardStep {
  double rough_left;        // the pattern's amplitude after one step, over δ
  double mean_off;          // |mean velocity − U| after the step, over δ
};
CheckerboardStep checkerboard_step(const VelocityTransfer& transfer) {
  const double h = 0.05, spacing = h / 2, delta = 0.01;
  const Vec2 U(0.1, 0.05);
  Solver solver = testing::elastic_solver(Grid(Vec2(0, 0), h, 20, 20), kDensity, 1e-6, kPoisson, transfer);
  const auto sign = [&](const Vec2& x) {
    const long i = std::lround(x.x() / spacing - 0.5), j = std::lround(x.y() / spacing - 0.5);
    return (i + j) % 2 == 0 ? 1.0 : -1.0;
  };
  for (int j = 8; j < 32; ++j)
    for (int i = 8; i < 32; ++i) {
      const Vec2 x = Vec2(i + 0.5, j + 0.5) * spacing;
      solver.add_point(0, x, spacing * spacing, spacing / 2, U + Vec2(sign(x) * delta, 0));
    }
  solver.step(1e-4);  // moves the points by U Δt, a 2 500th of their spacing
  double rough = 0, mass = 0;
  Vec2 momentum = Vec2::Zero();
  for (const MaterialPoint& mp : solver.points()) {
    rough += sign(mp.position) * (mp.velocity.x() - U.x());
    momentum += mp.mass * mp.velocity;
    mass += mp.mass;
  }
  return {rough / solver.points().size() / delta, (momentum / mass - U).norm() / delta};
}

TEST(Transfer, AFluctuationsRoughPartBlendsOutAtTheNoiseRateWithoutMomentum) {
  const CheckerboardStep flip = checkerboard_step(testing::apic_flip(0));
  const CheckerboardStep split = checkerboard_step(testing::apic_flip(0, 1e9));
  const CheckerboardStep pic = checkerboard_step(testing::apic());
  std::printf("point-to-point pattern left after one step: APIC-FLIP at rate 0 %.4f, its rough part at 1e9/s "
              "%.4f, APIC %.4f; mean velocity off U by %.1e, %.1e, %.1e of the pattern\n",
              flip.rough_left, split.rough_left, pic.rough_left, flip.mean_off, split.mean_off, pic.mean_off);
  EXPECT_NEAR(flip.rough_left, 1, 1e-6) << "FLIP keeps what the grid does not carry";
  // What is left of it is the part a round trip through the grid brings back, which APIC keeps
  // too: the two agree, and both are a small share of the pattern.
  EXPECT_LT(split.rough_left, 0.01);
  EXPECT_NEAR(split.rough_left, pic.rough_left, 0.002);
  // Σ_p m_p (d_p − s_p) = 0: blending the rough part out moves no momentum.
  EXPECT_LT(split.mean_off, 1e-9);
}

TEST(Transfer, BlendingOutTheRoughPartLeavesAResolvedModeUndamped) {
  // The bar's first mode is resolved by the grid: blending out the rough part of its fluctuations at
  // 500/s takes from the energy FLIP keeps a fifth of what blending out all of them at 500/s takes.
  const double dt = 1e-3, period = testing::kBarPeriod;
  const double flip = bar_energy_left(testing::apic_flip(0), dt, period);
  const double split = bar_energy_left(testing::apic_flip(0, 500), dt, period);
  const double blend = bar_energy_left(testing::apic_flip(500), dt, period);
  std::printf("bar energy left after one period: APIC-FLIP at rate 0 %.4f, its rough part at 500/s %.4f, "
              "all at 500/s %.4f\n", flip, split, blend);
  const double split_loss = 1 - split / flip, blend_loss = 1 - blend / flip;
  EXPECT_GT(blend_loss, 0.05) << "the test must tell a damping blend";
  EXPECT_LT(split_loss, 0.2 * blend_loss);
}

// Rebound speed / impact speed of one point thrown at 1 m/s onto an undamped frictionless line,
// with steps of ωΔt, ω = sqrt(k_n / m); `gap` sets where in a step the first contact falls.
double restitution(double omega_dt, double gap) {
  const double h = 0.1, radius = 0.025, speed = 1, k_n = 1e5;
  Solver solver = testing::elastic_solver(Grid(Vec2(0, 0), h, 10, 10), kDensity, kYoung, kPoisson);
  solver.add_obstacle(Obstacle(Polyline{{Vec2(0, 0.2), Vec2(1, 0.2)}, false}, ContactParameters{k_n, 0, 0, 0}));
  solver.add_point(0, Vec2(0.5, 0.2 + radius + gap), 4 * radius * radius, radius, Vec2(0, -speed));
  const double mass = solver.points()[0].mass;
  const double dt = omega_dt / std::sqrt(k_n / mass);
  for (int k = 0; k < 100000; ++k) {
    solver.step(dt);
    const MaterialPoint& mp = solver.points()[0];
    if (mp.velocity.y() > 0 && mp.position.y() > 0.2 + radius) return mp.velocity.y() / speed;
  }
  ADD_FAILURE() << "no rebound";
  return 0;
}

TEST(Transfer, PointBouncingOnAnUndampedObstacleGainsNoEnergy) {
  // Symplectic Euler (v += Δt a, then x += Δt v) keeps a shadow energy: the rebound differs from
  // the impact only by a bounded phase error of order (ωΔt)², never systematically. The former
  // update x += Δt (v + ½ Δt a) gained 4 / 8 / 17 % at ωΔt = 0.05 / 0.1 / 0.2.
  for (double omega_dt : {0.05, 0.1, 0.2})
    for (double gap : {1e-4, 3.3e-4, 7.7e-4}) {
      const double e = restitution(omega_dt, gap);
      std::printf("omega dt %.2f, gap %.1e: restitution %.5f\n", omega_dt, gap, e);
      EXPECT_LE(e, 1 + 0.25 * omega_dt * omega_dt);
      EXPECT_GE(e, 1 - 0.25 * omega_dt * omega_dt);
    }
}

}  // namespace
}  // namespace grainbank::mpm
