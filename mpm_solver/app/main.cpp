// mpm_solver: runs a 2D MPM scene (`mpm_solver SCENE.json ...`), writes a variant of a scene without
// running it (`mpm_solver scene`), the benchmark (`mpm_solver bench`), the audit of a run against
// live cells (`mpm_solver audit RUN`) or lists the constitutive laws (`mpm_solver laws [--json]`).
// Every error is one line on stderr starting with "mpm_solver: " and the exit code is 1.
#include <omp.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstring>
#include <exception>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "mpm_solver/app/audit_command.hpp"
#include "mpm_solver/app/bench_command.hpp"
#include "mpm_solver/app/laws_command.hpp"
#include "mpm_solver/laws/law_registry.hpp"
#include "common/json_input.hpp"
#include "common/stop_signals.hpp"
#include "mpm_solver/app/run_command.hpp"
#include "mpm_solver/app/scene_overrides.hpp"
#ifdef GRAINBANK_HAVE_MPI
#include "common/mpi_session.hpp"
#include "mpm_solver/parallel/mpi_ranks.hpp"
#endif

using namespace grainbank::mpm::app;

namespace {

// The flags that rewrite a scene, shared by a run and `mpm_solver scene`.
void add_override_options(CLI::App& cli, SceneOverrides& o) {
  cli.add_option("--law", o.law, "law of every DEM-backed material: " + grainbank::mpm::dem_backed_law_names());
  cli.add_option("--library", o.library, "cell library of every DEM-backed material (replaces \"cell\")");
  cli.add_option_function<std::string>(
      "--material", [&o](const std::string& text) { o.material = parse_material_patch(text); },
      "JSON object merged into every DEM-backed material (RFC 7396: null removes a key)");
  cli.add_option_function<std::vector<std::string>>(
         "--set",
         [&o](const std::vector<std::string>& texts) {
           for (const std::string& text : texts) o.settings.push_back(parse_setting(text));
         },
         "POINTER=JSON: sets one key of the scene, e.g. /time/end=0.05 (repeatable, applied in order)")
      ->allow_extra_args(false);
}

int scene_main(int argc, char** argv) {
  CLI::App cli("mpm_solver scene: writes SCENE.json as rewritten by the overrides, without running it; its cell and "
               "library paths are absolute, so the file can be run from anywhere");
  std::filesystem::path scene, out;
  SceneOverrides o;
  cli.add_option("scene", scene, "scene JSON file")->required();
  add_override_options(cli, o);
  cli.add_option("--out", out, "the scene file to write")->required();
  CLI11_PARSE(cli, argc, argv);
  const nlohmann::json doc = apply_overrides(grainbank::common::load_json_file(scene), scene.parent_path(), o);
  if (out.has_parent_path()) std::filesystem::create_directories(out.parent_path());
  std::ofstream file(out);
  file << doc.dump(2) << '\n';
  if (!file) throw std::runtime_error(out.string() + ": cannot write the scene");
  return 0;
}

int bench_main(int argc, char** argv) {
  CLI::App cli("mpm_solver bench: material-point updates/s (elastic) and live-DEM cost per point-step");
  BenchOptions o;
  bool json = false;
  cli.add_option("--points", o.points, "elastic points")->check(CLI::PositiveNumber);
  cli.add_option("--steps", o.steps, "elastic MPM steps")->check(CLI::PositiveNumber);
  cli.add_option("--threads", o.threads, "OpenMP threads (default: all)")->check(CLI::PositiveNumber);
  cli.add_option("--live-points", o.live_points, "live-DEM points (0: skip)")->check(CLI::NonNegativeNumber);
  cli.add_option("--live-steps", o.live_steps, "live-DEM MPM steps")->check(CLI::PositiveNumber);
  cli.add_flag("--json", json, "print the figures as JSON");
  CLI11_PARSE(cli, argc, argv);
  const nlohmann::json result = run_bench(o);
  if (json) std::printf("%s\n", result.dump(2).c_str());
  return 0;
}

int laws_main(int argc, char** argv) {
  CLI::App cli("mpm_solver laws: the constitutive laws a scene's materials can name, and the keys of each");
  bool json = false;
  cli.add_flag("--json", json, "print {\"laws\": {NAME: {\"keys\": [...], \"dem_backed\": bool}}}");
  CLI11_PARSE(cli, argc, argv);
  if (json) std::cout << law_catalogue().dump(2) << '\n';
  else print_law_table(std::cout);
  return 0;
}

int audit_main(int argc, char** argv) {
  CLI::App cli("mpm_solver audit: re-runs the audit trail of a run (scene key \"audit\": {\"points\": N}) with live "
               "DEM cells and reports the stress error of its cached point-steps");
  AuditCommandOptions o;
  int threads = 0;
  cli.add_option("run", o.run, "output folder of the run (its --out)")->required();
  cli.add_option("--threads", threads, "OpenMP threads (default: all)")->check(CLI::PositiveNumber);
  cli.add_flag("--json", o.json, "print the summary as JSON");
  std::string floor_cell;
  cli.add_option("--floor-cell", floor_cell,
                 "cell.json of the reference's recipe with another packing seed: also re-run the histories with "
                 "it and report its errors against the reference (the audit's noise floor)");
  CLI11_PARSE(cli, argc, argv);
  if (threads > 0) omp_set_num_threads(threads);
  if (!floor_cell.empty()) o.floor_cell = floor_cell;
  run_audit_command(o, std::cout);
  return 0;
}

int run_main(int argc, char** argv, const std::shared_ptr<const grainbank::mpm::Ranks>& ranks) {
  CLI::App cli("mpm_solver: 2D plane-strain MPM with analytic and live DEM laws\n"
               "usage: mpm_solver SCENE.json [--library LIB] [--law NAME] [--material JSON] [--set POINTER=JSON]... "
               "[--out DIR] [--restart FILE] [--checkpoint-every S] [--threads N] [--json] | mpm_solver scene --help | mpm_solver bench --help "
               "| mpm_solver audit --help");
  RunOptions o;
  int threads = 0;
  bool json = false;
  cli.add_option("scene", o.scene, "scene JSON file")->required();
  add_override_options(cli, o.overrides);
  cli.add_option("--out", o.out, "output folder (default mpm_out)");
  cli.add_option("--restart", o.restart, "resume from a restart file written by an earlier run of this scene");
  cli.add_option("--checkpoint-every", o.checkpoint_every,
                 "write OUT/restart.h5 at the first output snapshot after every S wall seconds, so that a killed "
                 "run can resume (default 600; 0: at every snapshot)")
      ->check(CLI::NonNegativeNumber);
  cli.add_option("--threads", threads, "OpenMP threads (default: all)")->check(CLI::PositiveNumber);
  cli.add_flag("--json", json, "print the run summary as JSON on stdout");
  CLI11_PARSE(cli, argc, argv);
  if (threads > 0) omp_set_num_threads(threads);
  o.progress = !json;
  o.stop = &grainbank::common::install_stop_signals();
  o.ranks = ranks;
  const bool root = !ranks || ranks->rank() == 0;
  const nlohmann::json summary = run_scene(o);
  if (!root) return summary["interrupted"].get<bool>() ? 1 : 0;
  if (summary["interrupted"].get<bool>()) {
    // Exit status 1, like an interrupted `dem_sampler sample`: the run did not reach its end time.
    if (json) std::printf("%s\n", summary.dump(2).c_str());
    const std::string restart = summary["restart"].get<std::string>();
    std::fprintf(stderr,
                 "mpm_solver: interrupted by %s at t = %.17g s (step %ld); restart written to %s; to resume, run the "
                 "same command with --restart %s and another --out\n",
                 grainbank::common::stop_signal() ? strsignal(grainbank::common::stop_signal())
                                                  : "a signal to another MPI rank",
                 summary["final_time"].get<double>(),
                 summary["steps"].get<long>(), restart.c_str(), restart.c_str());
    return 1;
  }
  if (json) {
    std::printf("%s\n", summary.dump(2).c_str());
  } else {
    std::printf("%ld steps, %zu points, t = %g s in %.3g s; outputs in %s\n", summary["steps"].get<long>(),
                summary["points"].get<std::size_t>(), summary["final_time"].get<double>(),
                summary["wall_time"]["total"].get<double>(), o.out.string().c_str());
  }
  return 0;
}

}  // namespace

// Under mpirun, a run is spread over the job's ranks (every rank runs this same command line); an
// error stops every rank at the same point (core/ranks.hpp share_failure) and rank 0 alone reports it.
int main(int argc, char** argv) {
  std::shared_ptr<const grainbank::mpm::Ranks> ranks;
#ifdef GRAINBANK_HAVE_MPI
  std::optional<grainbank::common::MpiSession> mpi;
  if (grainbank::common::MpiSession::launched_by_mpirun()) {
    mpi.emplace(&argc, &argv);
    ranks = std::make_shared<grainbank::mpm::parallel::MpiRanks>();
  }
#endif
  try {
    if (argc > 1 && std::string(argv[1]) == "scene") return scene_main(argc - 1, argv + 1);
    if (argc > 1 && std::string(argv[1]) == "bench") return bench_main(argc - 1, argv + 1);
    if (argc > 1 && std::string(argv[1]) == "audit") return audit_main(argc - 1, argv + 1);
    if (argc > 1 && std::string(argv[1]) == "laws") return laws_main(argc - 1, argv + 1);
    return run_main(argc, argv, ranks);
  } catch (const std::exception& e) {
    if (!ranks || ranks->rank() == 0) std::fprintf(stderr, "mpm_solver: %s\n", e.what());
    return 1;
  }
}
