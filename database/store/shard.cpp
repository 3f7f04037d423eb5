#include "database/store/shard.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace grainbank::db {
namespace {

constexpr const char* kFormat = "grainbank-shard-1";
// One record per chunk: a chunk holding committed records is never written again. With 256 rows per
// chunk, each append rewrote the last, partly committed chunk, and a SIGKILL during that write left
// committed rows behind a failing checksum. Costs (celldb bench, 2e5 records): inserts 1.2e6 -> 3e5
// records/s, index build 0.17 -> 0.56 s; both far from what DEM sampling or an MPM start notices.
constexpr hsize_t kChunkRows = 1;

std::int64_t parse_id(const h5::Object& where, const std::string& name) {
  try {
    std::size_t used = 0;
    const std::int64_t id = std::stoll(name, &used);
    if (used == name.size()) return id;
  } catch (const std::exception&) {
  }
  throw StoreError(where.file(), where.name() + "/" + name + ": unexpected member (expected a number)");
}

// A file's data, or a directory's entries, on disk: a rename is durable once both are.
void sync_to_disk(const std::filesystem::path& file) {
  const int fd = ::open(file.c_str(), O_RDONLY);
  const bool synced = fd >= 0 && ::fsync(fd) == 0;
  const int error = errno;
  if (fd >= 0) ::close(fd);
  if (!synced) throw StoreError(file, std::string("cannot sync to disk: ") + std::strerror(error));
}

}  // namespace

Shard Shard::create(const std::filesystem::path& file, const std::string& name, const std::string& parameter_hash) {
  Shard shard(h5::create_file(file));
  h5::write_attribute(shard.file_, "format", std::string(kFormat));
  h5::write_attribute(shard.file_, "shard", name);
  h5::write_attribute(shard.file_, "parameter_hash", parameter_hash);
  h5::create_group(shard.file_, "templates");
  h5::create_group(shard.file_, "paths");
  shard.flush();
  return shard;
}

Shard Shard::open(const std::filesystem::path& file, bool writable) {
  Shard shard(h5::open_file(file, writable));
  const std::string format = h5::read_string_attribute(shard.file_, "format");
  if (format != kFormat)
    throw StoreError(file, "not a grainbank shard (format \"" + format + "\", expected \"" + kFormat + "\")");
  if (!shard.has_group("/templates") || !shard.has_group("/paths"))
    throw StoreError(file, "damaged shard: /templates or /paths is missing");
  return shard;
}

std::string Shard::parameter_hash() const { return h5::read_string_attribute(file_, "parameter_hash"); }

void Shard::write_template(const std::string& token, const StoredCell& cell) {
  write_cell_state(h5::create_group(file_, template_group(token)), cell);
}

void Shard::create_path(std::int64_t path_id) {
  const h5::Object group = h5::create_group(file_, path_group(path_id));
  h5::create_group(group, "snapshots");
  const h5::Object table = h5::create_table(group, "records", kRecordColumns, kChunkRows);
  h5::write_attribute(table, "columns", record_column_names());
  h5::write_attribute(table, "units", record_column_units());
  h5::write_attribute(table, "stress_sign", std::string("tension-positive"));
}

h5::Object Shard::records_table(std::int64_t path_id) const {
  h5::Object table = h5::open_dataset(file_, path_group(path_id) + "/records");
  if (h5::table_columns(table) != kRecordColumns)
    throw StoreError(file(), table.name() + ": " + std::to_string(h5::table_columns(table)) + " columns, expected " +
                                 std::to_string(kRecordColumns));
  return table;
}

void Shard::append_records(std::int64_t path_id, const std::vector<Record>& records) {
  std::vector<double> rows;
  rows.reserve(records.size() * kRecordColumns);
  for (const Record& r : records) append_record_row(r, rows);
  h5::append_rows(records_table(path_id), rows);
}

void Shard::write_snapshot(std::int64_t path_id, std::int64_t record_index, const StoredCell& cell) {
  write_cell_state(h5::create_group(file_, snapshot_group(path_id, record_index)), cell);
}

void Shard::flush() { h5::flush(file_); }

std::uint64_t Shard::record_rows(std::int64_t path_id) const { return h5::table_rows(records_table(path_id)); }

std::vector<Record> Shard::read_records(std::int64_t path_id, std::uint64_t first, std::uint64_t count) const {
  const std::vector<double> rows = h5::read_rows(records_table(path_id), first, count);
  std::vector<Record> records;
  records.reserve(count);
  for (std::size_t k = 0; k < count; ++k) records.push_back(record_from_row(rows.data() + k * kRecordColumns));
  return records;
}

StoredCell Shard::read_cell(const std::string& group) const { return read_cell_state(h5::open_group(file_, group)); }

bool Shard::has_group(const std::string& group) const {
  // H5Lexists needs every intermediate link to exist: walk the path one member at a time.
  std::string prefix;
  std::size_t start = 1;
  while (start <= group.size()) {
    const std::size_t end = std::min(group.find('/', start), group.size());
    prefix.append("/").append(group, start, end - start);
    if (!h5::has_child(file_, prefix)) return false;
    start = end + 1;
  }
  return true;
}

std::vector<std::string> Shard::template_tokens() const { return h5::child_names(h5::open_group(file_, "/templates")); }

std::vector<std::int64_t> Shard::path_ids() const {
  const h5::Object paths = h5::open_group(file_, "/paths");
  std::vector<std::int64_t> ids;
  for (const std::string& name : h5::child_names(paths)) ids.push_back(parse_id(paths, name));
  return ids;
}

std::vector<std::int64_t> Shard::snapshot_indices(std::int64_t path_id) const {
  const std::string name = path_group(path_id) + "/snapshots";
  if (!has_group(name)) return {};
  const h5::Object snapshots = h5::open_group(file_, name);
  std::vector<std::int64_t> indices;
  for (const std::string& member : h5::child_names(snapshots)) indices.push_back(parse_id(snapshots, member));
  return indices;
}

void Shard::remove_group(const std::string& group) { h5::remove_child(file_, group); }

void Shard::truncate_records(std::int64_t path_id, std::uint64_t rows) { h5::resize_rows(records_table(path_id), rows); }

void Shard::rewrite_without(const std::filesystem::path& file, const Omitted& omitted) {
  const std::filesystem::path copy_file = std::filesystem::path(file).replace_extension(".repair.h5");
  std::filesystem::remove(copy_file);
  try {
    const Shard source = open(file, false);
    Shard copy = create(copy_file, h5::read_string_attribute(source.file_, "shard"), source.parameter_hash());
    const auto copy_kept = [&](const std::string& group) {
      if (!omitted.groups.count(group)) h5::copy_object(source.file_, copy.file_, group);
    };
    for (const std::string& token : source.template_tokens()) copy_kept(template_group(token));
    for (const std::int64_t id : source.path_ids()) {
      if (omitted.groups.count(path_group(id))) continue;
      // Rebuilt member by member: some of its snapshots or rows may be left out.
      const auto cut = omitted.rows_kept.find(id);
      if (cut == omitted.rows_kept.end()) {
        h5::create_group(h5::create_group(copy.file_, path_group(id)), "snapshots");
        h5::copy_object(source.file_, copy.file_, path_group(id) + "/records");
      } else {
        copy.create_path(id);
        copy.append_records(id, source.read_records(id, 0, cut->second));
      }
      for (const std::int64_t index : source.snapshot_indices(id)) copy_kept(snapshot_group(id, index));
    }
    copy.flush();
  } catch (...) {
    std::filesystem::remove(copy_file);
    throw;
  }
  sync_to_disk(copy_file);
  std::filesystem::rename(copy_file, file);
  sync_to_disk(std::filesystem::absolute(file).parent_path());
}

}  // namespace grainbank::db
