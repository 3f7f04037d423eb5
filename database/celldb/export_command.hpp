// `celldb export LIB --csv DIR`: the committed records as CSV, for spreadsheets and plotting.
//   DIR/paths.csv          one row per path: id, template, status, records, wall time, spec hash, file
//   DIR/path_<id>.csv      the path's committed records, header = record column names (record.hpp)
//   DIR/columns.csv        column name and unit
// Numbers are written with 17 significant digits, so they read back to the same doubles.
#pragma once
#include <filesystem>
#include <ostream>

namespace grainbank::celldb {

struct ExportOptions {
  std::filesystem::path library;
  std::filesystem::path csv_directory;  // created if missing; existing files of the same names are replaced
};

int run_export(const ExportOptions& options, std::ostream& out);

}  // namespace grainbank::celldb
