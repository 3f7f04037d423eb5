// The planar collapse of a cohesionless Drucker–Prager column (Lube et al. 2005), built through the
// solver's C++ interface: a column of width L0 and height a L0 against a back wall, held by a gate
// that is removed at t = 0.02 s, run until it is at rest (kinetic energy below 1e-4 of its peak).
#pragma once
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "mpm_solver/core/diagnostics.hpp"
#include "mpm_solver/laws/drucker_prager_law.hpp"
#include "tests/mpm/mpm_test_util.hpp"

namespace grainbank::mpm::testing {

struct ColumnSetup {
  double aspect_ratio = 1;      // a = H0 / L0
  double width = 0.2;           // L0 [m]
  double cell_size = 0.01;      // h [m]: L0 / h = 20
  int points_per_cell = 2;
  double step_factor = 0.3;     // the CFL number and the contact factor
  VelocityTransfer transfer;  // the default
};

struct ColumnResult {
  double runout = 0;        // ΔL / L0
  double final_height = 0;  // H∞ / H0
  double rest_time = 0;     // [s]
  long steps = 0;
};

// Lube et al. 2005, planar: ΔL/L0 ≈ 1.2 a for a ≲ 1.8, ≈ 1.9 a^(2/3) above.
inline double lube_runout(double a) { return a <= 1.8 ? 1.2 * a : 1.9 * std::cbrt(a * a); }

inline ColumnResult collapse(const ColumnSetup& c) {
  const double h = c.cell_size, L0 = c.width, H0 = c.aspect_ratio * L0, base = 2 * h, wall = 2 * h;
  const double gate_removal = 0.02, friction_angle = 30 * std::numbers::pi / 180;
  // Room for twice Lube's runout.
  const int cells_x = static_cast<int>(std::ceil((wall + L0 * (1 + 2 * lube_runout(c.aspect_ratio)) + 2 * h) / h));
  const int cells_y = static_cast<int>(std::ceil((base + H0 + 2 * h) / h));
  SolverSettings settings = settings_with(c.transfer);
  settings.time_step = {c.step_factor, c.step_factor};
  Solver solver(Grid(Vec2(0, 0), h, cells_x, cells_y), settings);
  const Elasticity elasticity{5e6, 0.3};
  solver.add_law(std::make_unique<DruckerPragerLaw>(1500, DruckerPragerParameters{elasticity, friction_angle, 0, 0, std::nullopt}));
  seed_region(solver, 0, rectangle(Vec2(wall, base), Vec2(wall + L0, base + H0)), c.points_per_cell);
  // Base and walls as stiff as the material over one cell (k_n = M / n², so that sqrt(k_n / m_p) = c_p / h);
  // base friction 0.5 and wall friction 0.3 as the example scenes.
  const double k_n = elasticity.p_wave_modulus() / (c.points_per_cell * c.points_per_cell);
  const double top = base + H0 + h;
  solver.add_obstacle(Obstacle(Polyline{{Vec2(-1, base), Vec2(cells_x * h + 1, base)}, false},
                               ContactParameters{k_n, k_n, 0.5, 0.5}));
  solver.add_obstacle(Obstacle(Polyline{{Vec2(wall, base), Vec2(wall, top)}, false}, ContactParameters{k_n, k_n, 0.3, 0.5}));
  solver.add_obstacle(Obstacle(Polyline{{Vec2(wall + L0, base), Vec2(wall + L0, top)}, false},
                               ContactParameters{k_n, k_n, 0.3, 0.5}, Vec2::Zero(), ObstacleRelease::at(gate_removal)));
  solver.set_gravity(Gravity{Vec2(0, -9.81), std::nullopt});

  const double radius = 0.5 * h / c.points_per_cell;
  double peak = 0;
  ColumnResult result;
  while (true) {
    solver.step(std::min(solver.stable_time_step(), 1e-3));
    const double kinetic = measure_flow(solver.points()).kinetic_energy;
    peak = std::max(peak, kinetic);
    if (solver.time() > gate_removal && kinetic < 1e-4 * peak) break;
    if (solver.time() > 20 * std::sqrt(H0 / 9.81) + 1) throw std::runtime_error("the column did not come to rest");
  }
  double front = 0, height = 0;
  for (const MaterialPoint& mp : solver.points())
    front = std::max(front, mp.position.x() + radius), height = std::max(height, mp.position.y() + radius);
  result.runout = (front - wall - L0) / L0;
  result.final_height = (height - base) / H0;
  result.rest_time = solver.time();
  result.steps = solver.steps();
  return result;
}

}  // namespace grainbank::mpm::testing
