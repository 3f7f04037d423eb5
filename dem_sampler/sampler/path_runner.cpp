#include "path_runner.hpp"

#include <chrono>
#include <cmath>
#include <sstream>

#include "library_record.hpp"

namespace grainbank::sampler {
namespace {

struct Abandoned {};

// The velocity gradient imposed over the increment ending at each record (record 0: none), laid out
// as the path driver lays out its increments.
std::vector<dem::Mat3> gradients_by_record(const app::PathSpec& path) {
  std::vector<dem::Mat3> L{dem::Mat3::Zero()};
  for (const app::PathSegment& segment : path.segments) {
    const app::PathSpec one{{segment}, path.record_interval, path.substepping};
    L.insert(L.end(), static_cast<std::size_t>(app::increment_count(one)), segment.L);
  }
  return L;
}

// DEM steps of the whole path, by the engine's own rule (substepping.hpp).
long dem_steps_of(const app::PathSpec& path, double dem_step) {
  long steps = 0;
  for (const app::PathSegment& segment : path.segments) {
    const app::PathSpec one{{segment}, path.record_interval, path.substepping};
    const long n = app::increment_count(one);
    const double last = segment.duration - static_cast<double>(n - 1) * path.record_interval;
    steps += (n - 1) * (n > 1 ? dem::substep_count(path.record_interval, dem_step, path.substepping.q_n) : 0) +
             dem::substep_count(last, dem_step, path.substepping.q_n);
  }
  return steps;
}

void check_finite(const app::PathRecord& r) {
  if (r.stress.allFinite() && r.F.allFinite() && std::isfinite(r.measures.kinetic_energy)) return;
  std::ostringstream s;
  s << "record " << r.index << " (t = " << r.time
    << " s): non-finite stress or deformation, the cell diverged (lower substepping q_t or the strain rate)";
  throw std::runtime_error(s.str());
}

}  // namespace

PathOutcome run_path(LibraryWriter& writer, std::int64_t path_id, const db::KeyScales& scales,
                     const RunnerOptions& options) {
  const auto start_time = std::chrono::steady_clock::now();
  const auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count(); };
  PathOutcome outcome;
  outcome.path_id = path_id;
  const PathWork work = writer.start(path_id);
  std::vector<db::Record> batch;
  const auto commit = [&] {
    writer.append(path_id, batch);
    outcome.records += static_cast<long>(batch.size());
    if (options.on_commit && !batch.empty()) writer.locked([&] { options.on_commit(static_cast<long>(batch.size())); });
    batch.clear();
  };
  try {
    dem::DemCell cell(work.start->state, writer.material(), work.start->skin);
    outcome.spheres = cell.size();
    const std::vector<dem::Mat3> L = gradients_by_record(work.plan.path);
    const long K = work.plan.snapshot_interval;
    app::drive_along_path(cell, work.plan.path, [&](const app::PathRecord& record) {
      check_finite(record);
      batch.push_back(to_library_record(record, L.at(static_cast<std::size_t>(record.index)), scales));
      if (K > 0 && record.index > 0 && record.index % K == 0) {
        commit();
        writer.snapshot(path_id, record.index, db::StoredCell{cell.state(), cell.skin()});
      } else if (static_cast<long>(batch.size()) >= options.commit_batch) {
        commit();
      }
      if (options.stop && options.stop->load()) throw Abandoned{};
    });
    commit();
    outcome.dem_steps = dem_steps_of(work.plan.path, cell.time_step(work.plan.path.substepping.q_t));
    outcome.wall_time = elapsed();
    writer.finish(path_id, db::PathStatus::done, outcome.wall_time);
  } catch (const Abandoned&) {
    writer.abandon(path_id);
    outcome.result = PathResult::abandoned;
    outcome.records = 0;
  } catch (const db::StoreError&) {
    throw;
  } catch (const std::exception& e) {
    commit();  // the records before the failure show how the cell got there
    outcome.result = PathResult::failed;
    outcome.error = e.what();
    outcome.wall_time = elapsed();
    writer.finish(path_id, db::PathStatus::failed, outcome.wall_time, outcome.error);
  }
  return outcome;
}

}  // namespace grainbank::sampler
