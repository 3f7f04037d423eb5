#include "database/celldb/info_command.hpp"

#include <iomanip>

#include "database/lookup/key_coverage.hpp"
#include "database/store/library.hpp"

namespace grainbank::celldb {
namespace {

std::uintmax_t file_size_or_zero(const std::filesystem::path& file) {
  std::error_code ignored;
  const std::uintmax_t size = std::filesystem::file_size(file, ignored);
  return ignored ? 0 : size;
}

std::string human_bytes(double bytes) {
  const char* units[] = {"B", "kB", "MB", "GB", "TB"};
  int unit = 0;
  while (bytes >= 1000 && unit < 4) {
    bytes /= 1000;
    ++unit;
  }
  std::ostringstream out;
  out << std::setprecision(3) << bytes << " " << units[unit];
  return out.str();
}

}  // namespace

nlohmann::json library_info(const std::filesystem::path& dir) {
  db::Library library = db::Library::open(dir);
  db::Catalogue& catalogue = library.catalogue();
  const auto meta = catalogue.all_meta();
  nlohmann::json info;
  info["library"] = dir.string();
  info["schema_version"] = std::stoi(meta.at("schema_version"));
  info["created_at"] = meta.at("created_at");
  info["created_by"] = meta.at("created_by");
  info["parameter_hash"] = library.parameter_hash();
  info["material"] = nlohmann::json::parse(meta.at("material"));
  info["units"] = nlohmann::json::parse(meta.at("units"));
  info["key_definition"] = nlohmann::json::parse(meta.at("key_definition"));
  info["counts"] = catalogue.table_counts();
  nlohmann::json paths = nlohmann::json::object();
  std::int64_t records = 0;
  for (const auto& [status, count] : catalogue.paths_by_status()) {
    paths[db::to_string(status)] = {{"paths", count.paths}, {"records", count.records}};
    records += count.records;
  }
  info["paths"] = paths;
  info["committed_records"] = records;

  const std::filesystem::path file = catalogue.file();
  std::uintmax_t catalogue_bytes = file_size_or_zero(file) + file_size_or_zero(file.string() + "-wal");
  nlohmann::json shards = nlohmann::json::array();
  std::uintmax_t shard_bytes = 0;
  for (const db::ShardRow& row : catalogue.shards()) {
    const std::uintmax_t bytes = file_size_or_zero(library.shard_path(row));
    shard_bytes += bytes;
    shards.push_back({{"name", row.name}, {"file", row.file}, {"writer", row.writer}, {"bytes", bytes}});
  }
  info["shards"] = shards;
  const lookup::KeyCoverage coverage = lookup::key_coverage(library);
  nlohmann::json ranges = nlohmann::json::object();
  const nlohmann::json components = info["key_definition"]["components"];
  for (std::size_t c = 0; c < components.size() && c < db::kKeySize; ++c)
    ranges[components[c].get<std::string>()] = {coverage.min[c], coverage.max[c]};
  info["key_coverage"] = {{"records", coverage.records}, {"occupied_unit_cells", coverage.occupied_cells},
                          {"range", ranges}};
  info["bytes"] = {{"catalogue", catalogue_bytes}, {"shards", shard_bytes}, {"total", catalogue_bytes + shard_bytes}};
  return info;
}

int run_info(const InfoOptions& options, std::ostream& out) {
  const nlohmann::json info = library_info(options.library);
  if (options.json) {
    out << info.dump(2) << "\n";
    return 0;
  }
  const auto& counts = info["counts"];
  out << "library         " << info["library"].get<std::string>() << "\n"
      << "schema version  " << info["schema_version"] << ", created " << info["created_at"].get<std::string>()
      << " by " << info["created_by"].get<std::string>() << "\n"
      << "parameter hash  " << info["parameter_hash"].get<std::string>() << "\n"
      << "material        " << info["material"].dump() << "\n"
      << "state key       scales " << info["key_definition"]["scales"].dump() << "\n"
      << "templates       " << counts["templates"] << "\n"
      << "paths           " << counts["paths"];
  for (const auto& [status, count] : info["paths"].items())
    out << ", " << status << " " << count["paths"] << " (" << count["records"] << " records)";
  out << "\n"
      << "records         " << info["committed_records"] << " committed\n"
      << "snapshots       " << counts["snapshots"] << "\n"
      << "shards          " << counts["shards"] << "\n";
  for (const auto& shard : info["shards"])
    out << "  " << shard["file"].get<std::string>() << "  " << human_bytes(shard["bytes"].get<double>()) << "  (writer "
        << shard["writer"].get<std::string>() << ")\n";
  const auto& coverage = info["key_coverage"];
  out << "key coverage    " << coverage["records"] << " records of done paths in " << coverage["occupied_unit_cells"]
      << " unit cells of the key space; ranges (key units):\n";
  for (const auto& [component, range] : coverage["range"].items())
    out << "  " << std::left << std::setw(10) << component << " [" << range[0].get<double>() << ", "
        << range[1].get<double>() << "]\n";
  out << "size            catalogue " << human_bytes(info["bytes"]["catalogue"].get<double>()) << ", shards "
      << human_bytes(info["bytes"]["shards"].get<double>()) << "\n";
  return 0;
}

}  // namespace grainbank::celldb
