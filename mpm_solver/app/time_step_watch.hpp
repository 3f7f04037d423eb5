// What a run does when its stable time step collapses or falls. A collapsed step (not positive, not
// a number, or below time.min_time_step) stops the run; a step that falls a hundredfold below the
// run's largest is reported and the run goes on. Both name the criterion that sets the step (seed
// Eq. 4 with the point, CFL, the obstacles' springs) and what to change.
#pragma once
#include <optional>
#include <string>

#include "mpm_solver/core/solver.hpp"

namespace grainbank::mpm::app {

// Whether no run can take this step: not positive or not a number, or below `floor`.
bool step_collapsed(double stable, double floor);

// The message of a collapsed step: when, what set it, what to change. Collective over ranks.
std::string time_step_collapse(const Solver& solver, double stable, double floor);

// Without time.min_time_step (0 by default) a collapsing step does not stop a run, it only slows it
// (stop 72: one lone front point took a run's step from 5.6 µs to 18 ns, and only the ETA showed it).
class StepFallWatch {
 public:
  static constexpr double kFirstReport = 100;
  // The report of a step that fell a hundredfold below the run's largest, and of every further
  // tenfold fall; nothing otherwise. Collective over ranks (every rank sees the same steps).
  std::optional<std::string> report(const Solver& solver, double stable);

 private:
  double largest_ = 0;
  double next_report_ = kFirstReport;
};

}  // namespace grainbank::mpm::app
