// dem_sampler: the command-line front end of the periodic DEM cell.
#include <CLI/CLI.hpp>
#include <iostream>
#include <nlohmann/json.hpp>

#include "benchmark_cell.hpp"
#include "run_command.hpp"

int main(int argc, char** argv) {
  using namespace grainbank::app;
  CLI::App app{"dem_sampler: periodic DEM cells driven along strain-rate paths"};
  app.require_subcommand(1);

  RunOptions run;
  std::string run_out;
  CLI::App* run_cmd = app.add_subcommand(
      "run", "Prepare (or load) the cell of CELL.json, drive it along PATH.json and tabulate t, F, ln det F, "
             "stress (tension-positive, Pa), p, q, phi, Z, N_b, D, kinetic energy");
  run_cmd->add_option("cell", run.cell_file, "CELL.json: material, effects, and preparation or packing file")
      ->required();
  run_cmd->add_option("--path", run.path_file, "PATH.json: segments of in-plane velocity gradient, record interval")
      ->required();
  run_cmd->add_option("--out", run_out, "write the table as CSV to this file instead of printing it");
  run_cmd->add_flag("--progress", run.progress, "report preparation and path progress on stderr");

  BenchmarkOptions bench;
  bool bench_json = false;
  CLI::App* bench_cmd = app.add_subcommand("bench", "Standard benchmark cell (shared/peers/README.md): particle-steps/s of simple shear");
  bench_cmd->add_option("--spheres", bench.spheres, "number of spheres")->check(CLI::Range(8, 10000000));
  bench_cmd->add_flag("--bonds", bench.bonds, "bond all close pairs (unbreakable) to measure the cost of bonds");
  bench_cmd->add_option("--steps", bench.shear_steps, "shear steps")->check(CLI::Range(100L, 1000000000L));
  bench_cmd->add_option("--seed", bench.seed, "seed of the random gas");
  bench_cmd->add_flag("--json", bench_json, "print a JSON object instead of text");

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "dem_sampler: " << e.what() << " (see dem_sampler --help)\n";
    return 1;
  }
  try {
    if (*run_cmd) {
      if (!run_out.empty()) run.out_file = run_out;
      run_path_command(run);
    }
    if (*bench_cmd) {
      const BenchmarkResult r = run_benchmark(bench);
      if (bench_json) {
        nlohmann::json j{{"spheres", bench.spheres}, {"bonds", bench.bonds}, {"shear_steps", bench.shear_steps},
                         {"particle_steps_per_second", r.particle_steps_per_second}, {"shear_seconds", r.shear_seconds},
                         {"contacts_per_sphere", r.contacts_per_sphere}, {"neighbours_per_sphere", r.neighbours_per_sphere},
                         {"bytes_per_sphere", r.bytes_per_sphere}, {"solid_fraction", r.solid_fraction},
                         {"pressure", r.pressure}, {"list_builds", r.list_builds}, {"flips", r.flips},
                         {"bond_count", r.bonds}};
        std::cout << j.dump(2) << "\n";
      } else {
        std::cout << "particle-steps/s: " << r.particle_steps_per_second << "\n"
                  << "shear phase: " << bench.shear_steps << " steps in " << r.shear_seconds << " s\n"
                  << "contacts per sphere: " << r.contacts_per_sphere << "\n"
                  << "Verlet pairs per sphere: " << r.neighbours_per_sphere << "\n"
                  << "memory per sphere: " << r.bytes_per_sphere << " B\n"
                  << "solid fraction: " << r.solid_fraction << ", pressure: " << r.pressure << "\n"
                  << "list rebuilds: " << r.list_builds << ", cell flips: " << r.flips << "\n";
        if (bench.bonds) std::cout << "bonds: " << r.bonds << "\n";
      }
    }
  } catch (const std::exception& e) {
    std::cerr << "dem_sampler: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
