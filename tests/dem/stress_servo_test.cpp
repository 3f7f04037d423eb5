// The stress servo (dem_sampler/cell/stress_servo.hpp) that brings a warm-started cell to a material
// point's stress: it reaches an anisotropic, sheared target, the cell then holds that stress at rest
// (a state, not a transient of the servo), and it reports failure instead of pretending, early
// when the target is beyond what the packing can carry.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "dem_sampler/cell/stress_servo.hpp"
#include "tests/dem/dem_test_util.hpp"

namespace grainbank::dem::test {
namespace {

// A prepared frictional cell at p0 = 1e4 Pa and servo settings at inertial number 1e-3.
struct ServoCase {
  Material material = small_material();
  DemCell cell = prepare_cell(material, small_spec(100, 31));
  double p0 = 1e4;
  StressServoSettings settings() const {
    StressServoSettings s;
    s.tolerance = 0.02 * p0;
    s.stress_scale = p0;
    s.max_rate = 1e-3 * std::sqrt(p0 / material.density) / 1e-3;
    s.dt = cell.time_step(0.1);
    s.max_steps = 200000;
    return s;
  }
};

// Isotropic compression at 1.3 p0 plus a deviator and an in-plane shear stress: a state the
// prepared isotropic cell is far from.
Mat3 anisotropic_target(double p0) {
  Mat3 t = -1.3 * p0 * Mat3::Identity();
  t(0, 0) += 0.15 * p0;
  t(1, 1) -= 0.15 * p0;
  t(0, 1) = t(1, 0) = 0.1 * p0;
  return t;
}

Mat3 mean_stress_at_rest(DemCell& cell, double dt, long steps) {
  Mat3 sum = Mat3::Zero();
  for (long k = 0; k < steps; ++k) {
    cell.step_with_velocity_gradient(Mat3::Zero(), dt);
    sum += cell.stress();
  }
  return sum / static_cast<double>(steps);
}

TEST(StressServo, BringsACellToAnAnisotropicStressThatItThenHoldsAtRest) {
  ServoCase c;
  const Mat3 target = anisotropic_target(c.p0);
  ASSERT_GT((c.cell.stress() - target).cwiseAbs().maxCoeff(), 0.2 * c.p0) << "the case must start far away";
  const StressServoSettings s = c.settings();
  const StressServoResult r = servo_to_stress(c.cell, target, s);
  std::printf("servo: %ld steps, residual %.1f Pa\n", r.steps, r.residual);
  ASSERT_TRUE(r.converged);
  EXPECT_LE(r.residual, s.tolerance);
  // Held still, the packing keeps that stress: within twice the tolerance (relaxation of a
  // quasi-static servo is small).
  const Mat3 rest = mean_stress_at_rest(c.cell, s.dt, 2000);
  EXPECT_LT((rest - target).cwiseAbs().maxCoeff(), 2 * s.tolerance) << rest;
}

TEST(StressServo, ReportsFailureWhenItRunsOutOfSteps) {
  ServoCase c;
  StressServoSettings s = c.settings();
  s.max_steps = 60;  // one window: far too few
  const StressServoResult r = servo_to_stress(c.cell, anisotropic_target(c.p0), s);
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.steps, 60);
  EXPECT_GT(r.residual, s.tolerance);
}

// A cohesionless packing cannot carry isotropic tension: the servo pulls it apart at full rate
// without progress, and gives up after `patience` windows rather than at max_steps.
TEST(StressServo, GivesUpOnAStressThePackingCannotCarry) {
  ServoCase c;
  const StressServoSettings s = c.settings();
  const StressServoResult r = servo_to_stress(c.cell, c.p0 * Mat3::Identity(), s);
  EXPECT_FALSE(r.converged);
  EXPECT_LT(r.steps, s.max_steps / 10);
  EXPECT_GT(r.residual, 0.5 * c.p0);
  EXPECT_TRUE(c.cell.stress().allFinite());
}

TEST(StressServo, RefusesBadTargetsAndSettings) {
  ServoCase c;
  Mat3 asymmetric = anisotropic_target(c.p0);
  asymmetric(0, 1) += 0.5 * c.p0;
  EXPECT_THROW(servo_to_stress(c.cell, asymmetric, c.settings()), std::invalid_argument);
  Mat3 nan_target = anisotropic_target(c.p0);
  nan_target(2, 2) = std::nan("");
  EXPECT_THROW(servo_to_stress(c.cell, nan_target, c.settings()), std::invalid_argument);
  StressServoSettings s = c.settings();
  s.tolerance = 0;
  EXPECT_THROW(servo_to_stress(c.cell, anisotropic_target(c.p0), s), std::invalid_argument);
}

}  // namespace
}  // namespace grainbank::dem::test
