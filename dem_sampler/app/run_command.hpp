// `dem_sampler run`: prepare (or load) one cell, drive it along one path, tabulate every record.
#pragma once
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include "dem_sampler/cell/dem_cell.hpp"

namespace grainbank::app {

struct RunOptions {
  std::filesystem::path cell_file;
  std::filesystem::path path_file;
  std::optional<std::filesystem::path> out_file;  // CSV; without it an aligned table goes to stdout
  bool progress = false;                          // preparation and path progress on stderr
  // Instead of CELL.json (cell_file empty): a cell from elsewhere, e.g. a library template, with a
  // description for the summary line.
  std::function<dem::DemCell()> cell_source;
  std::string cell_source_name;
};

// Reads and checks both inputs (and opens the output) before any expensive work, so input errors
// come first. Throws common::InputError for input problems, std::exception for engine failures.
void run_path_command(const RunOptions& options);

}  // namespace grainbank::app
