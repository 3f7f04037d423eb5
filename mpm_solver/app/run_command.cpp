#include "mpm_solver/app/run_command.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "mpm_solver/app/time_step_watch.hpp"
#include "mpm_solver/core/diagnostics.hpp"
#include "mpm_solver/io/audit_trail.hpp"
#include "mpm_solver/io/coupling_report.hpp"
#include "mpm_solver/io/restart.hpp"
#include "mpm_solver/io/scene_input.hpp"
#include "common/duration_text.hpp"
#include "common/recent_pace_eta.hpp"
#include "common/json_input.hpp"
#include "mpm_solver/io/series_csv.hpp"
#include "mpm_solver/io/tracked_cells.hpp"
#include "mpm_solver/io/vtu_writer.hpp"

namespace grainbank::mpm::app {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// Output times t_k = k · interval; `due` tells whether t reached the next one (within round-off).
struct Schedule {
  double interval;
  long next = 1;
  double next_time() const { return static_cast<double>(next) * interval; }
  bool due(double t) const { return t >= next_time() * (1 - 1e-12); }
};
// Index of the first output time after t (a restarted run continues the same schedule).
long next_after(double t, double interval) { return static_cast<long>(std::floor(t / interval * (1 + 1e-12))) + 1; }

nlohmann::json phases_json(const PhaseTimes& p) {
  return {{"contact", p.contact},           {"particles_to_grid", p.particles_to_grid},
          {"grid", p.grid},                 {"grid_to_particles_and_remap", p.grid_to_particles},
          {"stress", p.stress},             {"sort", p.sort}};
}

// The scene file of the run: the file itself, or with overrides its rewritten JSON, kept in
// the output folder under the scene's own name (so that loader errors name the same file and key).
// Only `write` writes the rewritten file (rank 0 of several).
std::filesystem::path scene_of_run(const RunOptions& o, bool write) {
  if (!o.overrides.any()) return o.scene;
  const std::filesystem::path rewritten = o.out / "scene" / o.scene.filename();
  if (!write) return rewritten;
  const nlohmann::json doc =
      apply_overrides(common::load_json_file(o.scene), o.scene.parent_path(), o.overrides);
  std::filesystem::create_directories(rewritten.parent_path());
  std::ofstream(rewritten) << doc.dump(2) << '\n';
  return rewritten;
}

io::Scene load_scene(const RunOptions& o, const std::filesystem::path& file, const Ranks& ranks) {
  if (file == o.scene) return io::load_scene(file, ranks.rank(), ranks.size());
  try {
    return io::load_scene(file, ranks.rank(), ranks.size());
  } catch (const common::InputError& e) {
    throw common::InputError(std::string(e.what()) + " (in the scene as rewritten by the command line: " +
                             file.string() + ")");
  }
}

// What each rank's costly points took, and what each of them cost (collective): the
// inputs of the MPI scaling model (workflows/mpi_scaling). Per point: seconds of its constitutive
// calls per step, for the points of laws spread over ranks (live cells).
nlohmann::json load_balance(const Solver& solver, const Ranks& ranks) {
  // The constitutive work of each rank, without its waits for the others.
  std::vector<double> by_rank(static_cast<std::size_t>(ranks.size()), 0.0);
  for (double seconds : solver.point_update_seconds()) by_rank[static_cast<std::size_t>(ranks.rank())] += seconds;
  const double steps = std::max(1.0, static_cast<double>(solver.steps()));
  std::vector<double> per_point = sum_over_ranks(ranks, solver.point_update_seconds());
  for (double& seconds : per_point) seconds /= steps;
  return {{"update_seconds_by_rank", sum_over_ranks(ranks, by_rank)},
          {"shared_bytes_per_step", solver.shared_update_bytes() / steps},
          {"rebalanced_points", solver.rebalanced_points()},
          {"point_update_seconds_per_step", per_point}};
}

// Each law's notes of its start or its end, a line each on stderr.
void print_law_notes(const Solver& solver, const std::vector<std::string>& material_names, bool at_end) {
  for (std::size_t k = 0; k < solver.law_count(); ++k)
    for (const std::string& note : (at_end ? solver.law(k).end_report() : solver.law(k).start_report()).notes)
      std::fprintf(stderr, "mpm_solver: note: material \"%s\" (%s): %s\n", material_names[k].c_str(),
                   solver.law(k).name().c_str(), note.c_str());
}

}  // namespace

nlohmann::json run_scene(const RunOptions& options) {
  const Clock::time_point start = Clock::now();
  const std::shared_ptr<const Ranks> ranks = options.ranks ? options.ranks : std::make_shared<OneRank>();
  const bool root = ranks->rank() == 0;
  // Runs `write` on rank 0 only; a failure there stops every rank with its message (a rank that
  // went on alone would wait for the others forever).
  const auto on_root = [&](auto&& write) {
    if (ranks->size() == 1) return write();
    std::string failure;
    if (root) try {
        write();
      } catch (const std::exception& e) {
        failure = e.what();
      }
    share_failure(*ranks, failure);
  };
  on_root([&] {
    std::filesystem::create_directories(options.out);
    scene_of_run(options, true);
  });
  const std::filesystem::path scene_file = scene_of_run(options, false);
  io::Scene scene = load_scene(options, scene_file, *ranks);
  Solver& solver = *scene.solver;
  solver.set_ranks(ranks);
  io::RunRecord run_record;
  if (!options.restart.empty()) run_record = io::read_restart(options.restart, solver);
  if (root && scene.stop_at_rest && run_record.kinetic_energy_peak_since > 0)
    std::fprintf(stderr,
                 "mpm_solver: warning: %s carries no kinetic-energy peak from before t = %g s (an older build's "
                 "restart, or one resumed from it): time.stop_at_rest compares with the peak from then on\n",
                 options.restart.string().c_str(), run_record.kinetic_energy_peak_since);
  if (root) print_law_notes(solver, scene.material_names, false);
  // Rank 0 writes every output; the other ranks step the same solver and measure the same flow.
  std::optional<io::AuditTrailRecorder> audit_trail;
  if (root && !scene.audited_points.empty())
    audit_trail.emplace(solver, scene.audited_points, std::filesystem::absolute(scene_file).string());
  const double setup_time = seconds_since(start);

  struct Outputs {
    io::PvdCollection pvd;
    io::SeriesCsv series;
    std::optional<io::TrackedCsv> tracked;
    io::TrackedCells tracked_cells;
  };
  std::optional<Outputs> outputs;
  on_root([&] {
    outputs.emplace(Outputs{io::PvdCollection(options.out / "points.pvd"), io::SeriesCsv(options.out / "series.csv"),
                            std::nullopt, io::TrackedCells(options.out / "cells", scene.tracked_points)});
    if (!scene.tracked_points.empty())
      outputs->tracked.emplace(options.out / "tracked_points.csv", scene.tracked_points);
  });

  const std::filesystem::path restart = options.out / "restart.h5";
  const auto write_restart = [&] {
    solver.gather_point_states();
    on_root([&] { io::write_restart(restart, solver, run_record); });
  };
  double output_time = 0;
  long snapshots = 0;
  Clock::time_point last_checkpoint = Clock::now();
  const auto snapshot = [&] {
    const Clock::time_point t0 = Clock::now();
    if (!scene.tracked_points.empty()) solver.gather_point_states(scene.tracked_points);
    on_root([&] {
      char name[64];
      std::snprintf(name, sizeof name, "points_%06ld.vtu", snapshots);
      io::write_vtu(options.out / name, solver);
      outputs->pvd.add(solver.time(), name);
      outputs->tracked_cells.write(solver, snapshots);
    });
    ++snapshots;
    // At a snapshot, so that a run resumed from the checkpoint starts on its own output schedule;
    // rank 0's clock decides for all.
    if (ranks->any(root && seconds_since(last_checkpoint) >= options.checkpoint_every)) {
      write_restart();
      last_checkpoint = Clock::now();
    }
    output_time += seconds_since(t0);
  };
  bool at_rest = false, front_reached = false;
  const auto record = [&](double dt) {
    const TimeStepLimits limits = solver.time_step_limits();
    FlowMeasures flow = measure_flow(solver.points());
    on_root([&] {
      flow = outputs->series.write(solver, dt, limits);
      if (outputs->tracked) outputs->tracked->write(solver);
    });
    run_record.kinetic_energy_peak = std::max(run_record.kinetic_energy_peak, flow.kinetic_energy);
    if (const auto& rest = scene.stop_at_rest)
      at_rest = solver.time() >= rest->not_before * (1 - 1e-12) &&
                flow.kinetic_energy < rest->kinetic_energy_fraction * run_record.kinetic_energy_peak;
    if (const auto& front = scene.stop_at_front)
      front_reached = solver.time() >= front->not_before * (1 - 1e-12) && flow.front >= front->x;
  };

  const Clock::time_point loop_start = Clock::now();
  snapshot();
  record(0);
  Schedule snapshots_due{scene.output_interval, next_after(solver.time(), scene.output_interval)};
  Schedule rows{scene.series_interval, next_after(solver.time(), scene.series_interval)};
  double dt_min = std::numeric_limits<double>::infinity(), dt_max = 0;
  StepFallWatch step_falls;
  std::vector<std::string> step_fall_reports;
  Clock::time_point last_report = loop_start;
  // The pace of the last minute: a column answered by a library while it stands costs far less per
  // simulated second than after its gate opens.
  common::RecentPaceEta eta(60);
  eta.record(0, solver.time() / scene.end_time);
  // A signal that reaches any rank stops all of them after the same step.
  const auto stop_requested = [&] { return ranks->any(options.stop && options.stop->load()); };
  while (solver.time() < scene.end_time * (1 - 1e-12) && !at_rest && !front_reached && !stop_requested()) {
    // Land exactly on the next output, row or end time.
    const double horizon = std::min({snapshots_due.next_time(), rows.next_time(), scene.end_time});
    const double stable = solver.stable_time_step();
    if (step_collapsed(stable, scene.min_time_step)) {
      const std::string cause = time_step_collapse(solver, stable, scene.min_time_step);
      write_restart();
      throw std::runtime_error(cause + "; restart written to " + restart.string());
    }
    if (const std::optional<std::string> fall = step_falls.report(solver, stable)) {
      step_fall_reports.push_back(*fall);
      if (root) std::fprintf(stderr, "%smpm_solver: warning: %s\n", options.progress ? "\n" : "", fall->c_str());
    }
    const double dt = std::min(stable, horizon - solver.time());
    solver.step(dt);
    if (audit_trail) audit_trail->record(solver, dt);
    dt_min = std::min(dt_min, dt), dt_max = std::max(dt_max, dt);
    if (rows.due(solver.time())) record(dt), ++rows.next;
    if (snapshots_due.due(solver.time())) snapshot(), ++snapshots_due.next;
    if (root && options.progress && seconds_since(last_report) > 2) {
      last_report = Clock::now();
      const double done = solver.time() / scene.end_time;
      eta.record(seconds_since(loop_start), done);
      std::fprintf(stderr, "\rt = %.4g s (%.1f%%), step %ld, dt = %.3g s, ETA %s   ", solver.time(), 100 * done,
                   solver.steps(), dt, common::duration_text(eta.eta()).c_str());
    }
  }
  if (root && options.progress) std::fprintf(stderr, "\n");
  const double run_time = seconds_since(loop_start);
  // Checked once: a signal arriving after the loop ended does not make a finished run "interrupted".
  const bool interrupted = solver.time() < scene.end_time * (1 - 1e-12) && !at_rest && !front_reached;
  write_restart();
  on_root([&] {
    if (audit_trail) io::write_audit_trail(options.out / io::kAuditTrailFile, audit_trail->trail());
  });

  const double updates = static_cast<double>(solver.steps()) * static_cast<double>(solver.points().size());
  nlohmann::json summary = {
      {"scene", options.scene.string()},
      {"output", options.out.string()},
      {"materials", scene.material_names},
      {"points", solver.points().size()},
      {"steps", solver.steps()},
      {"final_time", solver.time()},
      {"time_step", {{"min", solver.steps() ? dt_min : 0.0}, {"max", dt_max}, {"falls", step_fall_reports}}},
      {"snapshots", snapshots},
      {"threads", omp_get_max_threads()},
      {"mpi_ranks", ranks->size()},
      {"wall_time", {{"total", seconds_since(start)}, {"setup", setup_time}, {"steps", run_time - output_time},
                     {"output", output_time}, {"phases", phases_json(solver.phase_times())}}},
      {"point_updates_per_second", run_time > 0 ? updates / run_time : 0.0},
      // A study that resumes a stopped run adds its segments' CPU from here: the process that timed a
      // stopped segment from outside is gone by then.
      {"process_cpu_time", static_cast<double>(std::clock()) / CLOCKS_PER_SEC},
      {"interrupted", interrupted},
      {"at_rest", at_rest},
      {"front_reached", front_reached},
      {"kinetic_energy_peak", run_record.kinetic_energy_peak},
      {"kinetic_energy_peak_since", run_record.kinetic_energy_peak_since},
      {"restart", restart.string()}};
  if (audit_trail) summary["audit_trail"] = (options.out / io::kAuditTrailFile).string();
  summary["load"] = load_balance(solver, *ranks);
  solver.finish();
  if (root) print_law_notes(solver, scene.material_names, true);
  summary["coupling"] = io::coupling_summary(solver);
  on_root([&] { std::ofstream(options.out / "summary.json") << summary.dump(2) << '\n'; });
  return summary;
}

}  // namespace grainbank::mpm::app
