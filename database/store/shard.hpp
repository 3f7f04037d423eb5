// One HDF5 shard file of a library (shards/<name>.h5), written by exactly one process. Layout (see
// SCHEMA.md):
//   /                      attributes format, shard, parameter_hash
//   /templates/<token>     a template's prepared cell (cell_state_io.hpp layout)
//   /paths/<id>/records    chunked, extendible N × 37 table of records (record.hpp), column names
//                          and units as attributes
//   /paths/<id>/snapshots/<record index>   full cell state after that record
// The shard knows nothing of the catalogue: what is committed is decided there (library.hpp).
#pragma once
#include <cstdint>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "database/store/cell_state_io.hpp"
#include "database/store/hdf5_handle.hpp"
#include "database/store/record.hpp"

namespace grainbank::db {

class Shard {
 public:
  // Creates a new file (fails if it exists) and flushes its skeleton.
  static Shard create(const std::filesystem::path& file, const std::string& name, const std::string& parameter_hash);
  // Opens an existing shard; throws StoreError naming the file when it is not a readable shard.
  static Shard open(const std::filesystem::path& file, bool writable);

  const std::filesystem::path& file() const { return file_.file(); }
  std::string parameter_hash() const;

  static std::string template_group(const std::string& token) { return "/templates/" + token; }
  static std::string path_group(std::int64_t path_id) { return "/paths/" + std::to_string(path_id); }
  static std::string snapshot_group(std::int64_t path_id, std::int64_t record_index) {
    return path_group(path_id) + "/snapshots/" + std::to_string(record_index);
  }

  // Writers. None of them flushes: call flush() before committing what they wrote.
  void write_template(const std::string& token, const StoredCell& cell);
  void create_path(std::int64_t path_id);
  void append_records(std::int64_t path_id, const std::vector<Record>& records);
  void write_snapshot(std::int64_t path_id, std::int64_t record_index, const StoredCell& cell);
  void flush();

  // Readers.
  std::uint64_t record_rows(std::int64_t path_id) const;
  std::vector<Record> read_records(std::int64_t path_id, std::uint64_t first, std::uint64_t count) const;
  StoredCell read_cell(const std::string& group) const;
  bool has_group(const std::string& group) const;

  // Inventory and repair (verify.hpp).
  std::vector<std::string> template_tokens() const;
  std::vector<std::int64_t> path_ids() const;
  std::vector<std::int64_t> snapshot_indices(std::int64_t path_id) const;
  void remove_group(const std::string& group);
  void truncate_records(std::int64_t path_id, std::uint64_t rows);
  // What a rewrite leaves out: whole groups (each with everything below it), and the rows of some
  // records tables past a count (path id -> rows kept).
  struct Omitted {
    std::set<std::string> groups;
    std::map<std::int64_t, std::uint64_t> rows_kept;
  };
  // Replaces the shard file by a copy without what `omitted` names. HDF5 can neither unlink a group
  // whose object header a killed writer left half written, nor shrink a table whose chunk index it
  // left unreadable; a copy that leaves them out can (and gives back their space). The copy is
  // written next to the file as <name>.repair.h5, synced, then renamed over it: a crash leaves the
  // old file or the new one, plus at worst that stray copy. No writer may have the shard open.
  static void rewrite_without(const std::filesystem::path& file, const Omitted& omitted);

 private:
  explicit Shard(h5::Object file) : file_(std::move(file)) {}
  h5::Object records_table(std::int64_t path_id) const;
  h5::Object file_;
};

}  // namespace grainbank::db
