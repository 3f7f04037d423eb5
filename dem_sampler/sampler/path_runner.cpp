#include "dem_sampler/sampler/path_runner.hpp"

#include <chrono>
#include <cmath>
#include <sstream>

#include "dem_sampler/driver/path_driver.hpp"
#include "database/lookup/cell_record.hpp"

namespace grainbank::sampler {
namespace {

struct Abandoned {};

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
    const long K = work.plan.snapshot_interval;
    long dem_steps = 0;
    app::drive_along_path(cell, work.plan.path, [&](const app::PathRecord& record) {
      check_finite(record);
      dem_steps += record.substeps;
      batch.push_back(lookup::cell_record(cell, record.L, record.stress, scales));
      if (K > 0 && record.index > 0 && record.index % K == 0) {
        commit();
        writer.snapshot(path_id, record.index, db::StoredCell{cell.state(), cell.skin()});
      } else if (static_cast<long>(batch.size()) >= options.commit_batch) {
        commit();
      }
      if (options.stop && options.stop->load()) throw Abandoned{};
    });
    commit();
    outcome.dem_steps = dem_steps;
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
