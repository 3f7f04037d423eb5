// CELL.json: the material of a periodic DEM cell and where its spheres come from, either a
// preparation recipe (dem::prepare_cell) or a packing file made elsewhere (packing_csv.hpp).
// The schema is documented in README.md ("cell.json").
#pragma once
#include <filesystem>
#include <optional>

#include "dem_sampler/cell/dem_cell.hpp"
#include "dem_sampler/cell/preparation.hpp"

namespace grainbank::app {

struct CellInput {
  dem::Material material;                     // already passed dem::check
  std::optional<dem::PreparationSpec> preparation;  // exactly one of preparation and packing is set
  std::optional<std::filesystem::path> packing;     // resolved against the JSON file's folder
  double packing_skin = 0.1;                  // Verlet skin of a packing cell, fraction of the mean diameter
};

// Throws common::InputError naming the file and the JSON path of the first problem.
CellInput load_cell_input(const std::filesystem::path& file);

// Prepares the cell, or loads the packing (bonding close pairs when cohesion is on). Preparation
// failures propagate as std::runtime_error; packing file errors as common::InputError.
dem::DemCell build_cell(const CellInput& input, const dem::PreparationObserver& observer = {});

}  // namespace grainbank::app
