// dem_sampler: the command-line front end of the periodic DEM cell.
#include <CLI/CLI.hpp>
#include <iostream>
#include <nlohmann/json.hpp>

#include "dem_sampler/app/benchmark_cell.hpp"
#include "dem_sampler/app/prepare_command.hpp"
#include "dem_sampler/app/rheometer_command.hpp"
#include "dem_sampler/app/run_command.hpp"
#include "dem_sampler/app/sample_command.hpp"
#include "database/store/library.hpp"

int main(int argc, char** argv) {
  using namespace grainbank::app;
  CLI::App app{"dem_sampler: periodic DEM cells driven along strain-rate paths"};
  app.require_subcommand(1);

  RunOptions run;
  std::string run_out;
  CLI::App* run_cmd = app.add_subcommand(
      "run", "Prepare (or load) the cell of CELL.json, drive it along PATH.json and tabulate t, F, ln det F, "
             "stress (tension-positive, Pa), p, q, phi, Z, N_b, D, kinetic energy");
  std::filesystem::path run_library;
  std::int64_t run_template = 0;
  CLI::Option* run_cell = run_cmd->add_option("cell", run.cell_file, "CELL.json: material, effects, and preparation or packing file");
  CLI::Option* run_library_opt =
      run_cmd->add_option("--library", run_library, "start from a template of this cell library instead of CELL.json");
  CLI::Option* run_template_opt = run_cmd->add_option("--template", run_template, "template id in --library")
      ->needs(run_library_opt);
  run_library_opt->needs(run_template_opt)->excludes(run_cell);
  run_cmd->add_option("--path", run.path_file, "PATH.json: segments of in-plane velocity gradient, record interval")
      ->required();
  run_cmd->add_option("--out", run_out, "write the table as CSV to this file instead of printing it");
  run_cmd->add_flag("--progress", run.progress, "report preparation and path progress on stderr");

  PrepareOptions prepare;
  CLI::App* prepare_cmd = app.add_subcommand(
      "prepare", "Prepare the cell of CELL.json as a template of a cell library (created if absent); prints its id and "
                 "N, phi, Z, N_b, p, radii. An identical preparation already in the library is reused");
  prepare_cmd->add_option("cell", prepare.cell_file, "CELL.json: material, effects, and preparation or packing file")
      ->required();
  prepare_cmd->add_option("--library", prepare.library, "cell library directory")->required();
  prepare_cmd->add_flag("--progress", prepare.progress, "report preparation progress on stderr");

  SampleOptions sample;
  CLI::App* sample_cmd = app.add_subcommand(
      "sample", "Register the paths of PATHS.json in a cell library (each spec once) and run every pending path, "
                "paths in parallel on threads (and on MPI ranks under mpirun). Resumable");
  sample_cmd->add_option("paths", sample.paths_file, "PATHS.json: explicit, replay and generated paths")->required();
  sample_cmd->add_option("--library", sample.library, "cell library directory (made by dem_sampler prepare)")->required();
  sample_cmd->add_option("--threads", sample.threads, "worker threads per process (default: all cores; 1 per MPI rank)")
      ->check(CLI::Range(1, 4096));
  sample_cmd->add_option("--template", sample.template_id, "template id for the new paths (default: the only one)");
  sample_cmd->add_flag("--retry-failed", sample.retry_failed, "run failed paths again");
  sample_cmd->add_option("--commit-every", sample.commit_batch, "records per commit between snapshots")
      ->check(CLI::Range(1L, 1000000L));

  RheometerOptions rheometer;
  std::string rheometer_out;
  double rheometer_pressure = 0;
  CLI::App* rheometer_cmd = app.add_subcommand(
      "rheometer", "Steady simple shear of the cell of CELL.json, consolidated to -P, at each inertial number under a "
                   "controlled normal stress P; one row per I: I, shear rate, mu = sigma_xy / -sigma_yy (and its "
                   "standard error), normal stress, phi, Z, steps, the peak shear stress and its strain, and phi "
                   "after the consolidation");
  rheometer_cmd->add_option("cell", rheometer.cell_file, "CELL.json: material, effects, and preparation or packing file")
      ->required();
  rheometer_cmd->add_option("--inertial-numbers", rheometer.inertial_numbers, "inertial numbers I")
      ->required()->delimiter(',')->check(CLI::PositiveNumber);
  CLI::Option* rheometer_pressure_opt =
      rheometer_cmd->add_option("--pressure", rheometer_pressure, "normal stress P [Pa] (default: the preparation pressure)")
          ->check(CLI::PositiveNumber);
  rheometer_cmd->add_option("--strain", rheometer.strain, "total shear strain")->check(CLI::PositiveNumber);
  rheometer_cmd->add_option("--steady-from", rheometer.steady_from, "shear strain after which the flow counts as steady")
      ->check(CLI::NonNegativeNumber);
  rheometer_cmd->add_option("--out", rheometer_out, "write the rows as CSV to this file instead of printing them");

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
      if (run_library_opt->count()) {
        run.cell_source = [&] {
          grainbank::db::Library library = grainbank::db::Library::open(run_library);
          return library.restore(library.template_cell(run_template));
        };
        run.cell_source_name = "template " + std::to_string(run_template) + " of " + run_library.string();
      } else if (run.cell_file.empty()) {
        throw std::runtime_error("run: give CELL.json or --library LIB --template ID (see dem_sampler run --help)");
      }
      run_path_command(run);
    }
    if (*prepare_cmd) prepare_command(prepare);
    if (*rheometer_cmd) {
      if (rheometer_pressure_opt->count()) rheometer.normal_stress = rheometer_pressure;
      if (!rheometer_out.empty()) rheometer.out_file = rheometer_out;
      rheometer_command(rheometer);
    }
    if (*sample_cmd) return sample_command(sample);
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
        std::cout << "peers: LAMMPS 9.1 M, YADE 3.1 M particle-steps/s on this kind of machine, one core\n"
                  << "(shared/peers/README.md); for side-by-side ratios run workflows/benchmarks/dem_vs_peers.sh\n";
      }
    }
  } catch (const std::exception& e) {
    std::cerr << "dem_sampler: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
