// A cell library: directory LIB/ with catalogue.sqlite (what is committed) and shards/<name>.h5
// (bulk data, one writer process per file). The library is built for one material: templates and
// paths of any other material are refused with MaterialMismatch naming the differing parameters.
//
// Commit order, everywhere: HDF5 data written and flushed, then the catalogue row committed. A crash
// in between leaves HDF5 data nobody refers to (an orphan, removed by verify --repair) and never a
// committed row without its data. Readers only follow committed rows.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "database/store/catalogue.hpp"
#include "dem_sampler/cell/dem_cell.hpp"
#include "database/store/key_definition.hpp"
#include "database/store/shard.hpp"

namespace grainbank::db {

class Library {
 public:
  // Creates LIB/ (which must not exist, or be empty), its shards/ directory and catalogue.
  static Library create(const std::filesystem::path& dir, const dem::Material& material, const KeyScales& scales = {});
  // Opens an existing library, whatever its material.
  static Library open(const std::filesystem::path& dir);
  // Opens an existing library and refuses it (MaterialMismatch) unless it was built for `material`.
  static Library open(const std::filesystem::path& dir, const dem::Material& material);

  const std::filesystem::path& directory() const { return dir_; }
  const dem::Material& material() const { return material_; }
  const std::string& parameter_hash() const { return parameter_hash_; }
  KeyScales key_scales();
  Catalogue& catalogue() { return catalogue_; }

  // Throws MaterialMismatch ("<catalogue>: <what> was simulated with other physics: contact.friction:
  // library 0.5, given 0.4") unless `material` equals the library's.
  void require_material(const dem::Material& material, const std::string& what) const;

  // A pending path on a template; `spec` is the path's JSON (its hash is stored with it).
  std::int64_t add_path(std::int64_t template_id, const nlohmann::json& spec, const dem::Material& material);

  // Committed data only. Safe while other processes write the library: a read that meets a shard in
  // the middle of its writer's flush is retried (library.cpp), so readers never block writers.
  std::vector<Record> records(std::int64_t path_id);
  StoredCell template_cell(std::int64_t template_id);
  StoredCell snapshot_cell(std::int64_t path_id, std::int64_t record_index);
  // A live cell continuing from a stored state with the library's material.
  dem::DemCell restore(const StoredCell& cell) const;

  std::filesystem::path shard_path(const ShardRow& shard) const { return dir_ / shard.file; }
  Shard open_shard(std::int64_t shard_id, bool writable);

 private:
  Library(std::filesystem::path dir, Catalogue catalogue);
  std::filesystem::path dir_;
  Catalogue catalogue_;
  dem::Material material_;
  std::string parameter_hash_;
};

// The one writer of shards/<name>.h5 (create or resume). Each method writes and flushes HDF5, then
// commits its catalogue row, so it either completes or leaves only orphans behind.
class ShardWriter {
 public:
  ShardWriter(Library& library, const std::string& name);

  std::int64_t shard_id() const { return shard_id_; }
  Shard& shard() { return shard_; }

  // Stores a prepared cell; `preparation` is a JSON summary (spec, seed, report).
  std::int64_t add_template(const dem::Material& material, const nlohmann::json& preparation, const StoredCell& cell);
  // pending -> running in this shard: creates the path's records table.
  void start_path(std::int64_t path_id);
  // Appends after the committed records; drops uncommitted rows an earlier crash left behind.
  void append_records(std::int64_t path_id, const std::vector<Record>& records);
  // The cell state after committed record `record_index`.
  void add_snapshot(std::int64_t path_id, std::int64_t record_index, const StoredCell& cell);
  void finish_path(std::int64_t path_id, PathStatus status, double wall_time, const std::string& error = {});

 private:
  ShardWriter(Library& library, std::pair<std::int64_t, Shard> shard);
  PathRow own_running_path(std::int64_t path_id);
  void remove_leftover(const std::string& group);
  Library& library_;
  std::int64_t shard_id_;
  Shard shard_;
};

}  // namespace grainbank::db
