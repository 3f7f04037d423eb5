#include "dem_sampler/cell/stress_servo.hpp"

#include <algorithm>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace grainbank::dem {

namespace {

Mat3 symmetric_part(const Mat3& m) { return 0.5 * (m + m.transpose()); }

void check(const Mat3& target, const StressServoSettings& s) {
  auto fail = [](const char* what) { throw std::invalid_argument(std::string("stress servo: ") + what); };
  if (!target.allFinite()) fail("the target stress is not finite");
  if ((target - target.transpose()).cwiseAbs().maxCoeff() > 1e-12 * target.cwiseAbs().maxCoeff())
    fail("the target stress is not symmetric");
  if (!(s.tolerance > 0)) fail("tolerance: expected a positive stress [Pa]");
  if (!(s.stress_scale > 0)) fail("stress_scale: expected a positive stress [Pa]");
  if (!(s.max_rate > 0)) fail("max_rate: expected a positive strain rate [1/s]");
  if (!(s.dt > 0)) fail("dt: expected a positive time step [s]");
  if (s.window < 1) fail("window: expected at least one step");
  if (s.max_steps < 1) fail("max_steps: expected at least one step");
  if (s.patience < 1) fail("patience: expected at least one window");
}

}  // namespace

StressServoResult servo_to_stress(DemCell& cell, const Mat3& target, const StressServoSettings& settings) {
  check(target, settings);
  const double gain = settings.max_rate / settings.stress_scale;
  StressServoResult result;
  Mat3 sum = Mat3::Zero();
  long in_window = 0, stalled = 0;
  double best = std::numeric_limits<double>::infinity();
  while (result.steps < settings.max_steps) {
    // Too little compression (σ above its tension-positive target) shrinks the cell.
    const Mat3 error = target - symmetric_part(cell.stress());
    const Mat3 L = (gain * error).cwiseMax(-settings.max_rate).cwiseMin(settings.max_rate);
    cell.step_with_velocity_gradient(L, settings.dt);
    ++result.steps;
    sum += symmetric_part(cell.stress());
    if (++in_window < settings.window) continue;
    const Mat3 mean = sum / static_cast<double>(in_window);
    if (!mean.allFinite()) {
      std::ostringstream msg;
      msg << "stress servo: the cell's stress became non-finite after " << result.steps
          << " steps; lower the DEM time step (Q_t)";
      throw std::runtime_error(msg.str());
    }
    result.residual = (mean - target).cwiseAbs().maxCoeff();
    if (result.residual <= settings.tolerance) {
      result.converged = true;
      return result;
    }
    stalled = result.residual < 0.95 * best ? 0 : stalled + 1;
    best = std::min(best, result.residual);
    if (stalled >= settings.patience) return result;
    sum.setZero();
    in_window = 0;
  }
  return result;
}

}  // namespace grainbank::dem
