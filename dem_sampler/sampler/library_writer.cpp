#include "dem_sampler/sampler/library_writer.hpp"

#include "database/store/path_queue.hpp"
#include "dem_sampler/sampler/stored_path.hpp"

namespace grainbank::sampler {

db::KeyScales LibraryWriter::key_scales() {
  std::lock_guard lock(mutex_);
  return library_.key_scales();
}

PathWork LibraryWriter::start(std::int64_t path_id) {
  std::lock_guard lock(mutex_);
  const db::PathRow row = library_.catalogue().path(path_id);
  std::optional<PathPlan> plan = stored_plan(library_, row);
  if (!plan)
    throw db::StoreError(library_.catalogue().file(), "path " + std::to_string(path_id) +
                                                          ": not a sampler path (a live cell of an MPM run): nothing to run");
  PathWork work;
  work.path_id = path_id;
  work.plan = std::move(*plan);
  auto& cached = templates_[row.template_id];
  if (!cached) cached = std::make_shared<const db::StoredCell>(library_.template_cell(row.template_id));
  work.start = cached;
  shard_.start_path(path_id);
  return work;
}

void LibraryWriter::append(std::int64_t path_id, const std::vector<db::Record>& records) {
  if (records.empty()) return;
  std::lock_guard lock(mutex_);
  shard_.append_records(path_id, records);
}

void LibraryWriter::snapshot(std::int64_t path_id, std::int64_t record_index, const db::StoredCell& cell) {
  std::lock_guard lock(mutex_);
  shard_.add_snapshot(path_id, record_index, cell);
}

void LibraryWriter::finish(std::int64_t path_id, db::PathStatus status, double wall_time, const std::string& error) {
  std::lock_guard lock(mutex_);
  shard_.finish_path(path_id, status, wall_time, error);
}

void LibraryWriter::abandon(std::int64_t path_id) {
  std::lock_guard lock(mutex_);
  db::reset_paths(library_.catalogue(), {path_id});
}

}  // namespace grainbank::sampler
