// Helpers shared by the MPM tests: small scenes built through the solver's C++ interface.
#pragma once
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <string>

#include "mpm_solver/laws/elastic_law.hpp"
#include "mpm_solver/core/seeding.hpp"
#include "mpm_solver/core/solver.hpp"

namespace grainbank::mpm::testing {

// The velocity transfers: APIC, the FLIP/PIC blend with APIC's affine velocities at one rate or with
// its fluctuations' rough part at a rate of its own (VelocityTransfer{} is the default, 5 and 50/s),
// the FLIP/PIC blend with a PIC fraction per second, pure FLIP (rate 0) and pure PIC (rate ∞).
inline VelocityTransfer apic() { return {VelocityTransfer::Kind::apic}; }
inline VelocityTransfer apic_flip(double pic_rate) { return {VelocityTransfer::Kind::apic_flip, pic_rate, std::nullopt}; }
inline VelocityTransfer apic_flip(double pic_rate, double noise_rate) {
  return {VelocityTransfer::Kind::apic_flip, pic_rate, noise_rate};
}
inline VelocityTransfer flip_pic(double pic_rate) { return {VelocityTransfer::Kind::flip_pic, pic_rate, std::nullopt}; }
inline VelocityTransfer pure_flip() { return flip_pic(0); }
inline VelocityTransfer pure_pic() { return flip_pic(std::numeric_limits<double>::infinity()); }

inline std::string describe(const VelocityTransfer& t) {
  if (t.kind == VelocityTransfer::Kind::apic) return "apic";
  return (t.kind == VelocityTransfer::Kind::apic_flip ? "apic_flip" : "flip_pic") + std::string(", pic_rate ") +
         std::to_string(t.pic_rate) + "/s" +
         (t.noise_rate ? ", noise_rate " + std::to_string(*t.noise_rate) + "/s" : std::string());
}

inline SolverSettings settings_with(const VelocityTransfer& transfer) {
  SolverSettings s;
  s.transfer = transfer;
  return s;
}

// A solver with one elastic law (index 0).
inline Solver elastic_solver(const Grid& grid, double density, double young, double poisson,
                             const VelocityTransfer& transfer = apic()) {
  Solver solver(grid, settings_with(transfer));
  solver.add_law(std::make_unique<ElasticLaw>(density, Elasticity{young, poisson}));
  return solver;
}

// A free elastic bar (length 1 m, E = 100 Pa, ρ = 1 kg/m³, ν = 0: period 0.2 s) over 8 cells of 4 × 16
// points, vibrating in its first mode v = 0.01 cos(π x / L) m/s.
constexpr double kBarPeriod = 0.2;
inline Solver vibrating_bar(const VelocityTransfer& transfer) {
  const double length = 1, h = length / 8;
  Solver solver = elastic_solver(Grid(Vec2(0, 0), h, 12, 6), 1, 100, 0.0, transfer);
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 16; ++i) {
      const double xi = (i + 0.5) / 16;
      solver.add_point(0, Vec2(2 * h + xi * length, 2 * h + (j + 0.5) * h / 2), h * h / 4, h / 4,
                       Vec2(0.01 * std::cos(std::numbers::pi * xi), 0));
    }
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

// An elastic column (ν = 0, E = 5 MPa, ρ = 1000 kg/m³) 0.4 m wide and 1 m tall, n × n points per grid
// cell of 0.05 m, on a frictionless floor at y = 0.1 m, under gravity ramped in over 0.3 s, run to
// `end`. Its settled state is σ_yy = -ρ g (H - y), σ_xx = 0, y the initial height above the floor.
struct SelfWeightColumn {
  static constexpr double h = 0.05, width = 0.4, height = 1.0, base = 0.1, rho = 1000, g = 9.81;
  Solver solver;
  std::map<std::uint32_t, Vec2> initial_positions;

  SelfWeightColumn(const SolverSettings& settings, double end, int points_per_cell = 2)
      : solver(Grid(Vec2(0, 0), h, 12, 24), settings) {
    solver.add_law(std::make_unique<ElasticLaw>(rho, Elasticity{5e6, 0.0}));
    seed_region(solver, 0, rectangle(Vec2(0.1, base), Vec2(0.1 + width, base + height)), points_per_cell);
    solver.add_obstacle(Obstacle(Polyline{{Vec2(-1, base), Vec2(2, base)}, false}, ContactParameters{1e6, 0, 0, 1.0}));
    solver.set_gravity(Gravity{Vec2(0, -g), GravityRamp{Vec2::Zero(), 0.0, 0.3}});
    initial_positions = positions_by_id(solver);
    run_until(solver, end);
  }
  double initial_height_above_floor(const MaterialPoint& mp) const { return initial_positions.at(mp.id).y() - base; }
};

}  // namespace grainbank::mpm::testing
