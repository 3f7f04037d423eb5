#include "database/store/path_queue.hpp"

#include "database/store/material_parameters.hpp"

namespace grainbank::db {
namespace {

constexpr const char* kToPending =
    "UPDATE paths SET status = 'pending', shard_id = NULL, hdf5_group = NULL, record_count = 0, wall_time = 0, "
    "error = NULL, updated_at = ? WHERE ";

std::int64_t changes(SqliteConnection& db) { return sqlite3_changes(db.raw()); }

}  // namespace

std::vector<std::int64_t> pending_paths(Catalogue& catalogue) {
  std::vector<std::int64_t> ids;
  auto s = catalogue.connection().prepare("SELECT id FROM paths WHERE status = 'pending' ORDER BY id");
  while (s.step()) ids.push_back(s.integer(0));
  return ids;
}

std::optional<std::int64_t> find_path(Catalogue& catalogue, std::int64_t template_id, const std::string& spec) {
  auto s = catalogue.connection().prepare(
      "SELECT id FROM paths WHERE template_id = ? AND spec_hash = ? AND spec = ? ORDER BY id LIMIT 1");
  s.bind(1, template_id).bind(2, text_hash(spec)).bind(3, spec);
  if (!s.step()) return std::nullopt;
  const std::int64_t id = s.integer(0);
  s.run();
  return id;
}

std::int64_t reset_running_paths(Catalogue& catalogue) {
  SqliteConnection& db = catalogue.connection();
  SqliteTransaction transaction(db);
  // A path an MPM run recorded (its spec names the run) cannot be run again: what it committed is
  // kept as a finished path.
  db.prepare("UPDATE paths SET status = 'done', updated_at = ? WHERE status = 'running' AND "
             "json_extract(spec, '$.run') IS NOT NULL")
      .bind(1, utc_now())
      .run();
  db.execute("DELETE FROM snapshots WHERE path_id IN (SELECT id FROM paths WHERE status = 'running')");
  db.prepare(std::string(kToPending) + "status = 'running'").bind(1, utc_now()).run();
  const std::int64_t count = changes(db);
  transaction.commit();
  return count;
}

void reset_paths(Catalogue& catalogue, const std::vector<std::int64_t>& path_ids) {
  SqliteConnection& db = catalogue.connection();
  SqliteTransaction transaction(db);
  auto drop_snapshots = db.prepare(
      "DELETE FROM snapshots WHERE path_id = ? AND path_id IN (SELECT id FROM paths WHERE status = 'running')");
  auto to_pending = db.prepare(std::string(kToPending) + "id = ? AND status = 'running'");
  for (std::int64_t id : path_ids) {
    drop_snapshots.bind(1, id).run();
    to_pending.bind(1, utc_now()).bind(2, id).run();
  }
  transaction.commit();
}

std::int64_t retry_failed_paths(Catalogue& catalogue) {
  SqliteConnection& db = catalogue.connection();
  db.prepare(std::string(kToPending) + "status = 'failed'").bind(1, utc_now()).run();
  return changes(db);
}

}  // namespace grainbank::db
