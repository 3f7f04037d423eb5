#include "database/store/library.hpp"

#include <unistd.h>

#include <atomic>
#include <algorithm>
#include <chrono>
#include <thread>
#include <utility>

#include "database/store/material_parameters.hpp"

namespace grainbank::db {
namespace {

constexpr const char* kCatalogueName = "catalogue.sqlite";

std::string host_and_pid() {
  char host[256] = "unknown-host";
  gethostname(host, sizeof host - 1);
  return std::string(host) + ":" + std::to_string(getpid());
}

nlohmann::json parse_meta_json(Catalogue& catalogue, const std::string& name) {
  const std::string text = catalogue.meta(name);
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    throw StoreError(catalogue.file(), "meta entry \"" + name + "\" is not valid JSON: " + e.what());
  }
}

// Unique within and across processes: names the HDF5 group of a template before its row exists.
std::string fresh_token() {
  static std::atomic<std::uint64_t> counter{0};
  const auto now = std::chrono::steady_clock::now().time_since_epoch().count();
  return text_hash(host_and_pid() + "/" + std::to_string(now) + "/" + std::to_string(counter++));
}

// Reads committed data of a shard, retrying when the read fails. Readers take no file lock
// (hdf5_handle.hpp), so one may open a shard while its writer is in the middle of a flush and find
// the file momentarily inconsistent ("truncated file", a chunk checksum error). HDF5's checksums
// detect that rather than misread it, and the committed rows themselves never change, so reading
// again a moment later succeeds. A shard that is really damaged still fails, after ~0.3 s.
template <class Read>
auto read_committed(Read&& read) {
  for (int attempt = 0;; ++attempt) {
    try {
      return read();
    } catch (const StoreError&) {
      if (attempt == 9) throw;
      std::this_thread::sleep_for(std::chrono::milliseconds(std::min(1 << attempt, 50)));
    }
  }
}

}  // namespace

Library::Library(std::filesystem::path dir, Catalogue catalogue) : dir_(std::move(dir)), catalogue_(std::move(catalogue)) {
  const nlohmann::json material = parse_meta_json(catalogue_, "material");
  try {
    material_ = material_from_json(material);
  } catch (const std::exception& e) {
    throw StoreError(catalogue_.file(), std::string("meta entry \"material\": ") + e.what());
  }
  parameter_hash_ = catalogue_.meta("parameter_hash");
  if (parameter_hash_ != db::parameter_hash(material_))
    throw StoreError(catalogue_.file(), "meta parameter_hash " + parameter_hash_ +
                                            " does not match the stored material (catalogue edited by hand?)");
}

Library Library::create(const std::filesystem::path& dir, const dem::Material& material, const KeyScales& scales) {
  dem::check(material);
  if (std::filesystem::exists(dir) && !std::filesystem::is_empty(dir))
    throw StoreError(dir, "cannot create a library here: the directory is not empty");
  std::filesystem::create_directories(dir / "shards");
  const nlohmann::json units = {{"length", "m"},      {"time", "s"}, {"mass", "kg"},  {"stress", "Pa, tension-positive"},
                                {"energy", "J"},      {"strain_rate", "1/s"}};
  const std::map<std::string, std::string> meta = {
      {"units", units.dump()},
      {"material", material_to_json(material).dump()},
      {"parameter_hash", db::parameter_hash(material)},
      {"effects", material_to_json(material).at("effects").dump()},
      {"key_definition", key_definition_json(scales).dump()},
      {"created_at", utc_now()},
      {"created_by", "grainbank " + host_and_pid()},
  };
  return Library(dir, Catalogue::create(dir / kCatalogueName, meta));
}

Library Library::open(const std::filesystem::path& dir) {
  if (!std::filesystem::is_directory(dir)) throw StoreError(dir, "library directory is missing");
  return Library(dir, Catalogue::open(dir / kCatalogueName));
}

Library Library::open(const std::filesystem::path& dir, const dem::Material& material) {
  Library library = open(dir);
  library.require_material(material, "the given material");
  return library;
}

KeyScales Library::key_scales() {
  try {
    return key_scales_from_json(parse_meta_json(catalogue_, "key_definition"));
  } catch (const StoreError&) {
    throw;
  } catch (const std::exception& e) {
    throw StoreError(catalogue_.file(), std::string("meta entry \"key_definition\": ") + e.what());
  }
}

void Library::require_material(const dem::Material& material, const std::string& what) const {
  const std::vector<std::string> differences = material_differences(material_, material);
  if (differences.empty()) return;
  std::string message = "library built for other physics than " + what + ": ";
  for (std::size_t k = 0; k < differences.size(); ++k) message += (k ? "; " : "") + differences[k];
  throw MaterialMismatch(catalogue_.file(), message);
}

std::int64_t Library::add_path(std::int64_t template_id, const nlohmann::json& spec, const dem::Material& material) {
  require_material(material, "path on template " + std::to_string(template_id));
  const TemplateRow row = catalogue_.template_row(template_id);
  if (row.parameter_hash != parameter_hash_)
    throw MaterialMismatch(catalogue_.file(), "template " + std::to_string(template_id) + " has parameter hash " +
                                                  row.parameter_hash + ", the library " + parameter_hash_);
  return catalogue_.insert_path(template_id, spec.dump(), parameter_hash_);
}

Shard Library::open_shard(std::int64_t shard_id, bool writable) {
  return Shard::open(shard_path(catalogue_.shard(shard_id)), writable);
}

std::vector<Record> Library::records(std::int64_t path_id) {
  const PathRow path = catalogue_.path(path_id);
  if (!path.shard_id || path.record_count == 0) return {};
  return read_committed([&] {
    return open_shard(*path.shard_id, false).read_records(path_id, 0, static_cast<std::uint64_t>(path.record_count));
  });
}

StoredCell Library::template_cell(std::int64_t template_id) {
  const TemplateRow row = catalogue_.template_row(template_id);
  return read_committed([&] { return open_shard(row.shard_id, false).read_cell(row.hdf5_group); });
}

StoredCell Library::snapshot_cell(std::int64_t path_id, std::int64_t record_index) {
  for (const SnapshotRow& row : catalogue_.snapshots_of(path_id))
    if (row.record_index == record_index)
      return read_committed([&] { return open_shard(row.shard_id, false).read_cell(row.hdf5_group); });
  throw StoreError(catalogue_.file(), "path " + std::to_string(path_id) + " has no snapshot at record " +
                                          std::to_string(record_index));
}

dem::DemCell Library::restore(const StoredCell& cell) const { return dem::DemCell(cell.state, material_, cell.skin); }

namespace {
// Existing shard of this name (resumed), or a new file whose row is committed once it is flushed.
std::pair<std::int64_t, Shard> open_or_create_shard(Library& library, const std::string& name) {
  if (name.empty() || name.find_first_of("/\\") != std::string::npos || name.starts_with('.'))
    throw StoreError(library.directory(), "invalid shard name \"" + name + "\"");
  Catalogue& catalogue = library.catalogue();
  if (const auto row = catalogue.find_shard(name)) {
    Shard shard = Shard::open(library.shard_path(*row), true);
    if (shard.parameter_hash() != library.parameter_hash())
      throw MaterialMismatch(shard.file(), "shard parameter hash " + shard.parameter_hash() + " differs from the library's " +
                                               library.parameter_hash());
    return {row->id, std::move(shard)};
  }
  const std::string file = "shards/" + name + ".h5";
  if (std::filesystem::exists(library.directory() / file))
    throw StoreError(library.directory() / file,
                     "shard file exists but is not in the catalogue (left by a crash?): run celldb verify --repair");
  Shard shard = Shard::create(library.directory() / file, name, library.parameter_hash());
  return {catalogue.insert_shard(name, file, host_and_pid()), std::move(shard)};
}
}  // namespace

ShardWriter::ShardWriter(Library& library, const std::string& name)
    : ShardWriter(library, open_or_create_shard(library, name)) {}

ShardWriter::ShardWriter(Library& library, std::pair<std::int64_t, Shard> shard)
    : library_(library), shard_id_(shard.first), shard_(std::move(shard.second)) {}

std::int64_t ShardWriter::add_template(const dem::Material& material, const nlohmann::json& preparation,
                                       const StoredCell& cell) {
  library_.require_material(material, "the template");
  const std::string token = fresh_token();
  shard_.write_template(token, cell);
  shard_.flush();
  TemplateRow row;
  row.parameter_hash = library_.parameter_hash();
  row.material = material_to_json(material).dump();
  row.preparation = preparation.dump();
  row.spheres = static_cast<std::int64_t>(cell.state.radius.size());
  row.shard_id = shard_id_;
  row.hdf5_group = Shard::template_group(token);
  return library_.catalogue().insert_template(row);
}

void ShardWriter::start_path(std::int64_t path_id) {
  const PathRow path = library_.catalogue().path(path_id);
  if (path.status != PathStatus::pending)
    throw StoreError(library_.catalogue().file(),
                     "path " + std::to_string(path_id) + " is " + to_string(path.status) + ", expected pending");
  if (path.parameter_hash != library_.parameter_hash())
    throw MaterialMismatch(library_.catalogue().file(), "path " + std::to_string(path_id) + " has parameter hash " +
                                                            path.parameter_hash + ", the library " +
                                                            library_.parameter_hash());
  remove_leftover(Shard::path_group(path_id));
  shard_.create_path(path_id);
  shard_.flush();
  library_.catalogue().set_path_running(path_id, shard_id_, Shard::path_group(path_id));
}

// What an interrupted writer left at `group` holds nothing committed. A group whose object header
// the interruption left half written cannot be unlinked in place; `verify --repair` rewrites the
// shard without it.
void ShardWriter::remove_leftover(const std::string& group) {
  if (!shard_.has_group(group)) return;
  try {
    shard_.remove_group(group);
  } catch (const StoreError& e) {
    throw StoreError(library_.directory(), "cannot remove " + group + ", left damaged by an interrupted writer (" +
                                               e.what() + "); nothing committed is lost. Run `celldb verify " +
                                               library_.directory().string() + " --repair`, then run again.");
  }
}

PathRow ShardWriter::own_running_path(std::int64_t path_id) {
  PathRow path = library_.catalogue().path(path_id);
  if (path.status != PathStatus::running || path.shard_id != shard_id_)
    throw StoreError(shard_.file(), "path " + std::to_string(path_id) + " is not running in this shard");
  return path;
}

void ShardWriter::append_records(std::int64_t path_id, const std::vector<Record>& records) {
  const PathRow path = own_running_path(path_id);
  const auto committed = static_cast<std::uint64_t>(path.record_count);
  const std::uint64_t rows = shard_.record_rows(path_id);
  if (rows < committed)
    throw StoreError(shard_.file(), Shard::path_group(path_id) + "/records: " + std::to_string(rows) +
                                        " rows but " + std::to_string(committed) + " committed (data lost)");
  if (rows > committed) shard_.truncate_records(path_id, committed);
  shard_.append_records(path_id, records);
  shard_.flush();
  library_.catalogue().set_record_count(path_id, path.record_count + static_cast<std::int64_t>(records.size()));
}

void ShardWriter::add_snapshot(std::int64_t path_id, std::int64_t record_index, const StoredCell& cell) {
  const PathRow path = own_running_path(path_id);
  if (record_index < 0 || record_index >= path.record_count)
    throw StoreError(shard_.file(), "snapshot of path " + std::to_string(path_id) + " at record " +
                                        std::to_string(record_index) + ": only " + std::to_string(path.record_count) +
                                        " records are committed");
  for (const SnapshotRow& row : library_.catalogue().snapshots_of(path_id))
    if (row.record_index == record_index)
      throw StoreError(shard_.file(), "path " + std::to_string(path_id) + " already has a snapshot at record " +
                                          std::to_string(record_index));
  const std::string group = Shard::snapshot_group(path_id, record_index);
  remove_leftover(group);  // not committed (checked above)
  shard_.write_snapshot(path_id, record_index, cell);
  shard_.flush();
  library_.catalogue().insert_snapshot(path_id, record_index, shard_id_, group);
}

void ShardWriter::finish_path(std::int64_t path_id, PathStatus status, double wall_time, const std::string& error) {
  own_running_path(path_id);
  if (status != PathStatus::done && status != PathStatus::failed)
    throw std::invalid_argument("finish_path: status must be done or failed");
  library_.catalogue().finish_path(path_id, status, wall_time, error);
}

}  // namespace grainbank::db
