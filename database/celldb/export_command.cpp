#include "database/celldb/export_command.hpp"

#include <cstdio>
#include <fstream>

#include "database/store/library.hpp"

namespace grainbank::celldb {
namespace {

std::ofstream open_csv(const std::filesystem::path& file) {
  std::ofstream out(file);
  if (!out) throw db::StoreError(file, "cannot write the CSV file");
  return out;
}

std::string exact(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

void close_csv(std::ofstream& out, const std::filesystem::path& file) {
  out.close();
  if (!out) throw db::StoreError(file, "write failed (disk full?)");
}

}  // namespace

int run_export(const ExportOptions& options, std::ostream& out) {
  db::Library library = db::Library::open(options.library);
  std::filesystem::create_directories(options.csv_directory);
  const std::vector<std::string>& names = db::record_column_names();
  const std::vector<std::string>& units = db::record_column_units();

  const std::filesystem::path columns_file = options.csv_directory / "columns.csv";
  std::ofstream columns = open_csv(columns_file);
  columns << "column,unit\n";
  for (std::size_t c = 0; c < names.size(); ++c) columns << names[c] << "," << units[c] << "\n";
  close_csv(columns, columns_file);

  const std::filesystem::path index_file = options.csv_directory / "paths.csv";
  std::ofstream index = open_csv(index_file);
  index << "path,template,status,records,wall_time,spec_hash,file\n";
  std::int64_t files = 0, records = 0;
  for (const db::PathRow& path : library.catalogue().paths()) {
    std::string name;
    if (path.record_count > 0) {
      name = "path_" + std::to_string(path.id) + ".csv";
      const std::filesystem::path file = options.csv_directory / name;
      std::ofstream csv = open_csv(file);
      for (std::size_t c = 0; c < names.size(); ++c) csv << (c ? "," : "") << names[c];
      csv << "\n";
      std::vector<double> row;
      for (const db::Record& r : library.records(path.id)) {
        row.clear();
        db::append_record_row(r, row);
        for (std::size_t c = 0; c < row.size(); ++c) csv << (c ? "," : "") << exact(row[c]);
        csv << "\n";
      }
      close_csv(csv, file);
      ++files;
      records += path.record_count;
    }
    index << path.id << "," << path.template_id << "," << db::to_string(path.status) << "," << path.record_count << ","
          << exact(path.wall_time) << "," << path.spec_hash << "," << name << "\n";
  }
  close_csv(index, index_file);
  out << "exported " << records << " records of " << files << " paths to " << options.csv_directory.string() << "\n";
  return 0;
}

}  // namespace grainbank::celldb
