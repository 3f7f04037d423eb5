#include "mpm_solver/app/bench_command.hpp"

#include <omp.h>

#include <chrono>
#include <cmath>
#include <random>

#include "dem_sampler/cell/preparation.hpp"
#include "dem_sampler/cell/snow_preset.hpp"
#include "mpm_solver/laws/elastic_law.hpp"
#include "mpm_solver/dem_laws/live_dem_law.hpp"
#include "mpm_solver/core/seeding.hpp"

namespace grainbank::mpm::app {

namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// A square elastic block of about `points` points (2 × 2 per cell) with random velocities under
// gravity; returns point updates per second over `steps` steps with `threads` threads.
double elastic_rate(long points, long steps, int threads, const VelocityTransfer& transfer = {}) {
  omp_set_num_threads(threads);
  const int side = std::max(2, static_cast<int>(std::lround(std::sqrt(points / 4.0))));
  const double h = 0.01;
  SolverSettings settings;
  settings.transfer = transfer;
  Solver solver(Grid(Vec2(0, 0), h, side + 8, side + 8), settings);
  solver.add_law(std::make_unique<ElasticLaw>(1000, Elasticity{1e6, 0.3}));
  seed_region(solver, 0, rectangle(Vec2(4 * h, 4 * h), Vec2((side + 4) * h, (side + 4) * h)), 2);
  solver.set_gravity(Gravity{Vec2(0, -9.81), std::nullopt});
  const double dt = solver.stable_time_step();
  solver.step(dt);  // warm-up: first touch of the buffers, first sort
  const auto start = std::chrono::steady_clock::now();
  for (long k = 0; k < steps; ++k) solver.step(dt);
  return static_cast<double>(solver.points().size()) * static_cast<double>(steps) / seconds_since(start);
}

// The snow-like cell of the seed (workflows/demo/cell.json): 125 bonded spheres, d ≈ 0.37 mm.
dem::DemCell snow_cell() { return dem::prepare_cell(dem::snow_material(), dem::snow_preparation(125, 1)); }

}  // namespace

nlohmann::json run_bench(const BenchOptions& o) {
  const int threads = o.threads > 0 ? o.threads : omp_get_max_threads();
  nlohmann::json result;
  const double serial = elastic_rate(o.points, o.steps, 1);
  const double parallel = threads > 1 ? elastic_rate(o.points, o.steps, threads) : serial;
  result["elastic"] = {{"points", o.points}, {"steps", o.steps}, {"threads", threads},
                       {"point_updates_per_second_1_thread", serial},
                       {"point_updates_per_second", parallel}, {"speed_up", parallel / serial},
                       {"baseline_per_core", "5-8 M/s (DESIGN.md)"}};
  std::printf("elastic, cubic B-splines, MUSL, %ld points x %ld steps\n", o.points, o.steps);
  std::printf("point-updates/s: %.3g (1 thread), %.3g (%d threads, speed-up %.2f); DESIGN.md baseline 5-8 M/s per core\n",
              serial, parallel, threads, parallel / serial);
  // The default transfer's second round trip through the grid (its rough part's blend, stop 78)
  // against APIC-FLIP with one rate, the transfer before it.
  VelocityTransfer one_rate;
  one_rate.noise_rate.reset();
  const double one_rate_serial = elastic_rate(o.points, o.steps, 1, one_rate);
  result["elastic"]["point_updates_per_second_1_thread_one_rate_blend"] = one_rate_serial;
  std::printf("the rough part's blend: %.3g point-updates/s (1 thread) against %.3g with one rate (it costs %+.1f %% per step)\n",
              serial, one_rate_serial, 100 * (one_rate_serial / serial - 1));

  if (o.live_points > 0) {
    omp_set_num_threads(threads);
    const dem::DemCell cell = snow_cell();
    LiveDemSettings settings;
    Solver solver(Grid(Vec2(0, 0), 0.1, 8, 8), SolverSettings{});
    solver.add_law(std::make_unique<LiveDemLaw>(cell, settings));
    for (long k = 0; k < o.live_points; ++k)
      solver.add_point(0, Vec2(0.3 + 0.05 * (k % 8), 0.3 + 0.05 * (k / 8 % 8)), 0.0025, 0.025,
                       Vec2(0.1 * (k % 3), 0));
    solver.set_gravity(Gravity{Vec2(0, -9.81), std::nullopt});
    const auto start = std::chrono::steady_clock::now();
    for (long k = 0; k < o.live_steps; ++k) solver.step(o.live_time_step);
    const double per_point_step = seconds_since(start) * threads / static_cast<double>(o.live_points * o.live_steps);
    const long substeps = dem::substep_count(o.live_time_step, cell.time_step(settings.substepping.q_t),
                                             settings.substepping.q_n);
    const double particle_steps = static_cast<double>(cell.size() * substeps) / per_point_step;
    result["live"] = {{"points", o.live_points}, {"steps", o.live_steps}, {"spheres", cell.size()},
                      {"time_step", o.live_time_step}, {"substeps", substeps},
                      {"verlet_pairs", cell.pair_count()}, {"interacting_pairs", cell.interacting_pairs()},
                      {"particle_steps_per_second", particle_steps},
                      {"core_seconds_per_point_step", per_point_step}, {"reference_seconds_per_point_step", 16e-3}};
    std::printf("live DEM, %zu spheres, dt = %g s, %ld sub-steps: %.2f ms per point-step (core time); reference "
                "implementation ~16 ms (125 spheres, ~104 sub-steps)\n",
                cell.size(), o.live_time_step, substeps, 1e3 * per_point_step);
    std::printf("  %.3g particle-steps/s; the cell at rest: %zu Verlet pairs, %lld in contact or bonded\n",
                particle_steps, cell.pair_count(), static_cast<long long>(cell.interacting_pairs()));
  }
  return result;
}

}  // namespace grainbank::mpm::app
