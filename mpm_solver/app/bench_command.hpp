// `mpm_solver bench`: material-point updates per second of the elastic law (cubic B-splines, MUSL),
// with its OpenMP speed-up, and the cost of one live-DEM point per MPM step.
#pragma once
#include <nlohmann/json.hpp>

namespace grainbank::mpm::app {

struct BenchOptions {
  long points = 100000;   // elastic points
  long steps = 100;       // elastic MPM steps
  int threads = 0;        // 0: OpenMP's default
  long live_points = 4;   // points with a 125-sphere live cell (0: skip)
  long live_steps = 3;
  double live_time_step = 1e-4;  // [s]
};

// Runs the benchmark; the result holds every figure printed.
nlohmann::json run_bench(const BenchOptions& options);

}  // namespace grainbank::mpm::app
