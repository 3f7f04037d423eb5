// The SQLite catalogue of a library (catalogue.sqlite): what is committed. Tables and columns are
// documented in SCHEMA.md; this class is the only code that writes SQL for them. A row is committed
// only after the HDF5 data it refers to has been flushed (library.hpp enforces the order).
#pragma once
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "database/store/sqlite_handle.hpp"

namespace grainbank::db {

inline constexpr int kSchemaVersion = 1;

enum class PathStatus { pending, running, done, failed };
std::string to_string(PathStatus status);
PathStatus path_status_from(const std::string& text);

struct ShardRow {
  std::int64_t id = 0;
  std::string name;
  std::string file;  // relative to the library directory
  std::string writer;
  std::string created_at;
};

struct TemplateRow {
  std::int64_t id = 0;
  std::string parameter_hash;
  std::string material;     // JSON (material_parameters.hpp)
  std::string preparation;  // JSON summary: spec, seed, report
  std::int64_t spheres = 0;
  std::int64_t shard_id = 0;
  std::string hdf5_group;
  std::string created_at;
};

struct PathRow {
  std::int64_t id = 0;
  std::int64_t template_id = 0;
  std::string spec;  // JSON
  std::string spec_hash;
  std::string parameter_hash;
  PathStatus status = PathStatus::pending;
  std::optional<std::int64_t> shard_id;  // set when a writer starts the path
  std::string hdf5_group;
  std::int64_t record_count = 0;  // committed records: rows [0, record_count) of the records table
  double wall_time = 0;           // [s]
  std::string error;
  std::string created_at, updated_at;
};

struct SnapshotRow {
  std::int64_t id = 0;
  std::int64_t path_id = 0;
  std::int64_t record_index = 0;
  std::int64_t shard_id = 0;
  std::string hdf5_group;
};

class Catalogue {
 public:
  // Creates the file and its tables and writes `meta` (schema_version added). Fails if it exists.
  static Catalogue create(const std::filesystem::path& file, const std::map<std::string, std::string>& meta);
  // Throws StoreError naming the file when it is missing, not a database, not a grainbank catalogue,
  // or written by a newer schema.
  static Catalogue open(const std::filesystem::path& file);

  const std::filesystem::path& file() const { return db_.file(); }
  SqliteConnection& connection() { return db_; }

  std::string meta(const std::string& name);
  std::map<std::string, std::string> all_meta();

  std::int64_t insert_shard(const std::string& name, const std::string& file, const std::string& writer);
  std::optional<ShardRow> find_shard(const std::string& name);
  ShardRow shard(std::int64_t id);
  std::vector<ShardRow> shards();

  std::int64_t insert_template(const TemplateRow& row);
  TemplateRow template_row(std::int64_t id);
  std::vector<TemplateRow> templates();

  std::int64_t insert_path(std::int64_t template_id, const std::string& spec, const std::string& parameter_hash);
  PathRow path(std::int64_t id);
  std::vector<PathRow> paths();
  void set_path_running(std::int64_t id, std::int64_t shard_id, const std::string& hdf5_group);
  void set_record_count(std::int64_t id, std::int64_t record_count);
  void finish_path(std::int64_t id, PathStatus status, double wall_time, const std::string& error);

  void insert_snapshot(std::int64_t path_id, std::int64_t record_index, std::int64_t shard_id, const std::string& group);
  std::vector<SnapshotRow> snapshots();
  std::vector<SnapshotRow> snapshots_of(std::int64_t path_id);
  // Deletes the snapshot rows of these ids in one transaction (their HDF5 groups become orphans).
  void delete_snapshots(const std::vector<std::int64_t>& ids);

  // Rows of every table, and paths and committed records per status, for `celldb info`.
  std::map<std::string, std::int64_t> table_counts();
  struct StatusCount {
    std::int64_t paths = 0, records = 0;
  };
  std::map<PathStatus, StatusCount> paths_by_status();

 private:
  explicit Catalogue(const std::filesystem::path& file, bool create) : db_(file, create) {}
  SqliteConnection db_;
};

// UTC time as 2024-01-31T12:34:56Z.
std::string utc_now();

}  // namespace grainbank::db
