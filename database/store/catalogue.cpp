#include "database/store/catalogue.hpp"

#include <ctime>

#include "database/store/material_parameters.hpp"

namespace grainbank::db {
namespace {

// Version 1 of the schema; SCHEMA.md describes every column. Later versions add migrations here.
constexpr const char* kSchema = R"sql(
CREATE TABLE meta (
  name  TEXT PRIMARY KEY,
  value TEXT NOT NULL
);
CREATE TABLE shards (
  id         INTEGER PRIMARY KEY,
  name       TEXT NOT NULL UNIQUE,
  file       TEXT NOT NULL UNIQUE,
  writer     TEXT NOT NULL,
  created_at TEXT NOT NULL
);
CREATE TABLE templates (
  id             INTEGER PRIMARY KEY,
  parameter_hash TEXT NOT NULL,
  material       TEXT NOT NULL,
  preparation    TEXT NOT NULL,
  spheres        INTEGER NOT NULL,
  shard_id       INTEGER NOT NULL REFERENCES shards(id),
  hdf5_group     TEXT NOT NULL,
  created_at     TEXT NOT NULL
);
CREATE TABLE paths (
  id             INTEGER PRIMARY KEY,
  template_id    INTEGER NOT NULL REFERENCES templates(id),
  spec           TEXT NOT NULL,
  spec_hash      TEXT NOT NULL,
  parameter_hash TEXT NOT NULL,
  status         TEXT NOT NULL DEFAULT 'pending' CHECK (status IN ('pending', 'running', 'done', 'failed')),
  shard_id       INTEGER REFERENCES shards(id),
  hdf5_group     TEXT,
  record_count   INTEGER NOT NULL DEFAULT 0,
  wall_time      REAL NOT NULL DEFAULT 0,
  error          TEXT,
  created_at     TEXT NOT NULL,
  updated_at     TEXT NOT NULL
);
CREATE INDEX paths_by_status ON paths(status);
CREATE INDEX paths_by_template ON paths(template_id);
CREATE TABLE snapshots (
  id           INTEGER PRIMARY KEY,
  path_id      INTEGER NOT NULL REFERENCES paths(id),
  record_index INTEGER NOT NULL,
  shard_id     INTEGER NOT NULL REFERENCES shards(id),
  hdf5_group   TEXT NOT NULL,
  UNIQUE (path_id, record_index)
);
CREATE TABLE audits (
  id         INTEGER PRIMARY KEY,
  created_at TEXT NOT NULL,
  details    TEXT NOT NULL
);
CREATE TABLE runs (
  id         INTEGER PRIMARY KEY,
  started_at TEXT NOT NULL,
  command    TEXT NOT NULL,
  details    TEXT NOT NULL
);
)sql";

constexpr const char* kPathColumns =
    "id, template_id, spec, spec_hash, parameter_hash, status, shard_id, hdf5_group, record_count, wall_time, "
    "error, created_at, updated_at";

PathRow path_from(const SqliteStatement& s) {
  PathRow r;
  r.id = s.integer(0);
  r.template_id = s.integer(1);
  r.spec = s.text(2);
  r.spec_hash = s.text(3);
  r.parameter_hash = s.text(4);
  r.status = path_status_from(s.text(5));
  if (!s.is_null(6)) r.shard_id = s.integer(6);
  r.hdf5_group = s.text(7);
  r.record_count = s.integer(8);
  r.wall_time = s.real(9);
  r.error = s.text(10);
  r.created_at = s.text(11);
  r.updated_at = s.text(12);
  return r;
}

constexpr const char* kTemplateColumns =
    "id, parameter_hash, material, preparation, spheres, shard_id, hdf5_group, created_at";

TemplateRow template_from(const SqliteStatement& s) {
  return TemplateRow{s.integer(0), s.text(1), s.text(2), s.text(3), s.integer(4), s.integer(5), s.text(6), s.text(7)};
}

ShardRow shard_from(const SqliteStatement& s) { return ShardRow{s.integer(0), s.text(1), s.text(2), s.text(3), s.text(4)}; }

SnapshotRow snapshot_from(const SqliteStatement& s) {
  return SnapshotRow{s.integer(0), s.integer(1), s.integer(2), s.integer(3), s.text(4)};
}

}  // namespace

std::string to_string(PathStatus status) {
  switch (status) {
    case PathStatus::pending: return "pending";
    case PathStatus::running: return "running";
    case PathStatus::done: return "done";
    case PathStatus::failed: return "failed";
  }
  return "?";
}

PathStatus path_status_from(const std::string& text) {
  for (PathStatus s : {PathStatus::pending, PathStatus::running, PathStatus::done, PathStatus::failed})
    if (to_string(s) == text) return s;
  throw std::invalid_argument("unknown path status \"" + text + "\"");
}

std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return text;
}

Catalogue Catalogue::create(const std::filesystem::path& file, const std::map<std::string, std::string>& meta) {
  if (std::filesystem::exists(file)) throw StoreError(file, "a catalogue already exists here");
  Catalogue catalogue(file, true);
  SqliteTransaction transaction(catalogue.db_);
  catalogue.db_.execute(kSchema);
  auto insert = catalogue.db_.prepare("INSERT INTO meta (name, value) VALUES (?, ?)");
  insert.bind(1, std::string("schema_version")).bind(2, std::to_string(kSchemaVersion)).run();
  for (const auto& [name, value] : meta) insert.bind(1, name).bind(2, value).run();
  transaction.commit();
  return catalogue;
}

Catalogue Catalogue::open(const std::filesystem::path& file) {
  if (!std::filesystem::exists(file))
    throw StoreError(file, "catalogue is missing: not a grainbank library (create one first)");
  Catalogue catalogue(file, false);
  auto has_meta = catalogue.db_.prepare("SELECT count(*) FROM sqlite_master WHERE type = 'table' AND name = 'meta'");
  has_meta.step();
  if (has_meta.integer(0) == 0) throw StoreError(file, "not a grainbank catalogue (no meta table)");
  const std::string text = catalogue.meta("schema_version");
  int version = 0;
  try {
    version = std::stoi(text);
  } catch (const std::exception&) {
    throw StoreError(file, "meta schema_version \"" + text + "\" is not a number");
  }
  if (version > kSchemaVersion)
    throw StoreError(file, "schema version " + std::to_string(version) + " is newer than this build supports (" +
                               std::to_string(kSchemaVersion) + "); use a newer grainbank");
  if (version < 1) throw StoreError(file, "schema version " + text + " is not a released grainbank schema");
  return catalogue;
}

std::string Catalogue::meta(const std::string& name) {
  auto s = db_.prepare("SELECT value FROM meta WHERE name = ?");
  s.bind(1, name);
  if (!s.step()) throw StoreError(file(), "meta entry \"" + name + "\" is missing");
  return s.text(0);
}

std::map<std::string, std::string> Catalogue::all_meta() {
  std::map<std::string, std::string> out;
  auto s = db_.prepare("SELECT name, value FROM meta");
  while (s.step()) out[s.text(0)] = s.text(1);
  return out;
}

std::int64_t Catalogue::insert_shard(const std::string& name, const std::string& file, const std::string& writer) {
  db_.prepare("INSERT INTO shards (name, file, writer, created_at) VALUES (?, ?, ?, ?)")
      .bind(1, name)
      .bind(2, file)
      .bind(3, writer)
      .bind(4, utc_now())
      .run();
  return db_.last_insert_id();
}

std::optional<ShardRow> Catalogue::find_shard(const std::string& name) {
  auto s = db_.prepare("SELECT id, name, file, writer, created_at FROM shards WHERE name = ?");
  s.bind(1, name);
  if (!s.step()) return std::nullopt;
  ShardRow row = shard_from(s);
  s.run();
  return row;
}

ShardRow Catalogue::shard(std::int64_t id) {
  auto s = db_.prepare("SELECT id, name, file, writer, created_at FROM shards WHERE id = ?");
  s.bind(1, id);
  if (!s.step()) throw StoreError(file(), "no shard with id " + std::to_string(id));
  ShardRow row = shard_from(s);
  s.run();
  return row;
}

std::vector<ShardRow> Catalogue::shards() {
  std::vector<ShardRow> rows;
  auto s = db_.prepare("SELECT id, name, file, writer, created_at FROM shards ORDER BY id");
  while (s.step()) rows.push_back(shard_from(s));
  return rows;
}

std::int64_t Catalogue::insert_template(const TemplateRow& row) {
  db_.prepare(
         "INSERT INTO templates (parameter_hash, material, preparation, spheres, shard_id, hdf5_group, created_at) "
         "VALUES (?, ?, ?, ?, ?, ?, ?)")
      .bind(1, row.parameter_hash)
      .bind(2, row.material)
      .bind(3, row.preparation)
      .bind(4, row.spheres)
      .bind(5, row.shard_id)
      .bind(6, row.hdf5_group)
      .bind(7, utc_now())
      .run();
  return db_.last_insert_id();
}

TemplateRow Catalogue::template_row(std::int64_t id) {
  auto s = db_.prepare(std::string("SELECT ") + kTemplateColumns + " FROM templates WHERE id = ?");
  s.bind(1, id);
  if (!s.step()) throw StoreError(file(), "no template with id " + std::to_string(id));
  TemplateRow row = template_from(s);
  s.run();
  return row;
}

std::vector<TemplateRow> Catalogue::templates() {
  std::vector<TemplateRow> rows;
  auto s = db_.prepare(std::string("SELECT ") + kTemplateColumns + " FROM templates ORDER BY id");
  while (s.step()) rows.push_back(template_from(s));
  return rows;
}

std::int64_t Catalogue::insert_path(std::int64_t template_id, const std::string& spec, const std::string& parameter_hash) {
  const std::string now = utc_now();
  db_.prepare(
         "INSERT INTO paths (template_id, spec, spec_hash, parameter_hash, created_at, updated_at) "
         "VALUES (?, ?, ?, ?, ?, ?)")
      .bind(1, template_id)
      .bind(2, spec)
      .bind(3, text_hash(spec))
      .bind(4, parameter_hash)
      .bind(5, now)
      .bind(6, now)
      .run();
  return db_.last_insert_id();
}

PathRow Catalogue::path(std::int64_t id) {
  auto s = db_.prepare(std::string("SELECT ") + kPathColumns + " FROM paths WHERE id = ?");
  s.bind(1, id);
  if (!s.step()) throw StoreError(file(), "no path with id " + std::to_string(id));
  PathRow row = path_from(s);
  s.run();
  return row;
}

std::vector<PathRow> Catalogue::paths() {
  std::vector<PathRow> rows;
  auto s = db_.prepare(std::string("SELECT ") + kPathColumns + " FROM paths ORDER BY id");
  while (s.step()) rows.push_back(path_from(s));
  return rows;
}

void Catalogue::set_path_running(std::int64_t id, std::int64_t shard_id, const std::string& hdf5_group) {
  db_.prepare("UPDATE paths SET status = 'running', shard_id = ?, hdf5_group = ?, updated_at = ? WHERE id = ?")
      .bind(1, shard_id)
      .bind(2, hdf5_group)
      .bind(3, utc_now())
      .bind(4, id)
      .run();
}

void Catalogue::set_record_count(std::int64_t id, std::int64_t record_count) {
  db_.prepare("UPDATE paths SET record_count = ?, updated_at = ? WHERE id = ?")
      .bind(1, record_count)
      .bind(2, utc_now())
      .bind(3, id)
      .run();
}

void Catalogue::finish_path(std::int64_t id, PathStatus status, double wall_time, const std::string& error) {
  auto s = db_.prepare("UPDATE paths SET status = ?, wall_time = ?, error = ?, updated_at = ? WHERE id = ?");
  s.bind(1, to_string(status)).bind(2, wall_time);
  if (error.empty())
    s.bind_null(3);
  else
    s.bind(3, error);
  s.bind(4, utc_now()).bind(5, id).run();
}

void Catalogue::insert_snapshot(std::int64_t path_id, std::int64_t record_index, std::int64_t shard_id,
                                const std::string& group) {
  db_.prepare("INSERT INTO snapshots (path_id, record_index, shard_id, hdf5_group) VALUES (?, ?, ?, ?)")
      .bind(1, path_id)
      .bind(2, record_index)
      .bind(3, shard_id)
      .bind(4, group)
      .run();
}

void Catalogue::delete_snapshots(const std::vector<std::int64_t>& ids) {
  SqliteTransaction transaction(db_);
  auto s = db_.prepare("DELETE FROM snapshots WHERE id = ?");
  for (const std::int64_t id : ids) s.bind(1, id).run();
  transaction.commit();
}

std::vector<SnapshotRow> Catalogue::snapshots() {
  std::vector<SnapshotRow> rows;
  auto s = db_.prepare("SELECT id, path_id, record_index, shard_id, hdf5_group FROM snapshots ORDER BY id");
  while (s.step()) rows.push_back(snapshot_from(s));
  return rows;
}

std::vector<SnapshotRow> Catalogue::snapshots_of(std::int64_t path_id) {
  std::vector<SnapshotRow> rows;
  auto s = db_.prepare(
      "SELECT id, path_id, record_index, shard_id, hdf5_group FROM snapshots WHERE path_id = ? ORDER BY record_index");
  s.bind(1, path_id);
  while (s.step()) rows.push_back(snapshot_from(s));
  return rows;
}

std::map<std::string, std::int64_t> Catalogue::table_counts() {
  std::map<std::string, std::int64_t> counts;
  for (const char* table : {"shards", "templates", "paths", "snapshots", "audits", "runs"}) {
    auto s = db_.prepare(std::string("SELECT count(*) FROM ") + table);
    s.step();
    counts[table] = s.integer(0);
    s.run();
  }
  return counts;
}

std::map<PathStatus, Catalogue::StatusCount> Catalogue::paths_by_status() {
  std::map<PathStatus, StatusCount> counts;
  auto s = db_.prepare("SELECT status, count(*), total(record_count) FROM paths GROUP BY status");
  while (s.step()) counts[path_status_from(s.text(0))] = StatusCount{s.integer(1), static_cast<std::int64_t>(s.real(2))};
  return counts;
}

}  // namespace grainbank::db
