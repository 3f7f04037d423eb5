// Helpers shared by the MPM tests: small scenes built through the solver's C++ interface.
#pragma once
#include <map>
#include <memory>

#include "core/elastic_law.hpp"
#include "core/seeding.hpp"
#include "core/solver.hpp"

namespace grainbank::mpm::testing {

inline SolverSettings settings_with_flip(double flip) {
  SolverSettings s;
  s.flip = flip;
  return s;
}

// A solver with one elastic law (index 0).
inline Solver elastic_solver(const Grid& grid, double density, double young, double poisson, double flip) {
  Solver solver(grid, settings_with_flip(flip));
  solver.add_law(std::make_unique<ElasticLaw>(density, Elasticity{young, poisson}));
  return solver;
}

// Advances to `end` with the solver's stable step (the last step shortened to land on `end`),
// calling observe(solver) after every step.
template <class Observer>
void run_until(Solver& solver, double end, Observer&& observe) {
  while (solver.time() < end * (1 - 1e-12)) {
    solver.step(std::min(solver.stable_time_step(), end - solver.time()));
    observe(solver);
  }
}
inline void run_until(Solver& solver, double end) {
  run_until(solver, end, [](const Solver&) {});
}

// Initial position of every point by id.
inline std::map<std::uint32_t, Vec2> positions_by_id(const Solver& solver) {
  std::map<std::uint32_t, Vec2> out;
  for (const MaterialPoint& mp : solver.points()) out[mp.id] = mp.position;
  return out;
}

}  // namespace grainbank::mpm::testing
