// `dem_sampler rheometer`: the μ(I) of a cell (cell/shear_rheometer.hpp). The cell of CELL.json is
// prepared once; each inertial number shears a copy of it and gives one row.
#pragma once
#include <filesystem>
#include <optional>
#include <vector>

namespace grainbank::app {

struct RheometerOptions {
  std::filesystem::path cell_file;
  std::vector<double> inertial_numbers;
  std::optional<double> normal_stress;  // [Pa]; default: the preparation pressure of CELL.json
  double strain = 3, steady_from = 1;
  std::optional<std::filesystem::path> out_file;  // CSV; without it the rows go to stdout
};

// Input errors (common::InputError) name the file; engine failures name CELL.json.
void rheometer_command(const RheometerOptions& options);

}  // namespace grainbank::app
