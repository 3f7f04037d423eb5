#include "mpm_solver/app/time_step_watch.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace grainbank::mpm::app {

namespace {

// Why the stable step is what it is: the criterion that sets it (and where the law's own limit does,
// the point), and what to change. Collective (law_limiting_point).
struct StepLimitCause {
  std::string what, remedy;
  bool law = false;
};

StepLimitCause step_limit_cause(const Solver& solver) {
  const TimeStepLimits limits = solver.time_step_limits();
  if (limits.law <= limits.minimum()) {
    const MaterialPoint& mp = solver.law_limiting_point();
    std::ostringstream what;
    what << "it is set by seed Eq. 4 (q_h d_min / |dh/dt|, the law's own limit) of material point " << mp.id << " (law "
         << solver.law(mp.law).name() << ") at (" << mp.position.x() << ", " << mp.position.y() << "), |L| = "
         << mp.velocity_gradient.norm() << " 1/s, V/V0 = " << mp.volume / mp.initial_volume
         << "; a DEM cell whose grains still touch, stretched far beyond its template or deformed very fast, sets it";
    return {what.str(), "raise the material's q_h", true};
  }
  if (limits.wave <= limits.minimum())
    return {"it is set by the CFL criterion (a point's wave speed plus its speed over the grid cell)",
            "look for a point whose density m/V has collapsed (an expanded, stress-free point) or whose speed is not "
            "physical"};
  return {"it is set by the obstacles' contact springs (contact_factor sqrt(m_min / k_n))",
          "lower the obstacles' k_n or look for a point whose mass is tiny"};
}

std::string step_fell_to(const Solver& solver, double stable) {
  std::ostringstream msg;
  msg << "the time step fell to " << stable << " s at t = " << solver.time() << " s (step " << solver.steps() << ")";
  return msg.str();
}

}  // namespace

// Not positive: a signal speed that overflowed, or a point whose mass underflowed.
bool step_collapsed(double stable, double floor) { return !(stable > 0) || stable < floor; }

std::string time_step_collapse(const Solver& solver, double stable, double floor) {
  const StepLimitCause cause = step_limit_cause(solver);
  const bool below_floor = stable > 0;
  std::ostringstream msg;
  msg << step_fell_to(solver, stable);
  if (below_floor)
    msg << ", below time.min_time_step = " << floor << " s";
  else
    msg << ", which no step can advance";
  msg << ": " << cause.what << ": " << cause.remedy
      << (cause.law && below_floor ? ", or lower time.min_time_step to go on at this step" : "");
  return msg.str();
}

std::optional<std::string> StepFallWatch::report(const Solver& solver, double stable) {
  if (!(stable > 0)) return std::nullopt;
  largest_ = std::max(largest_, stable);
  if (!(stable * next_report_ <= largest_)) return std::nullopt;
  while (stable * next_report_ <= largest_) next_report_ *= 10;
  const StepLimitCause cause = step_limit_cause(solver);
  std::ostringstream report;
  report << step_fell_to(solver, stable) << ", 1/" << std::lround(largest_ / stable) << " of the run's largest ("
         << largest_ << " s): " << cause.what << ": " << cause.remedy << "; time.min_time_step stops a run at such a step";
  return report.str();
}

}  // namespace grainbank::mpm::app
