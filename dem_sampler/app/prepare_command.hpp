// `dem_sampler prepare CELL.json --library LIB`: the cell template every path of LIB starts from.
#pragma once
#include <filesystem>

namespace grainbank::app {

struct PrepareOptions {
  std::filesystem::path cell_file;
  std::filesystem::path library;  // created (for CELL.json's material) when absent or empty
  bool progress = false;          // preparation progress on stderr
};

// Prints "template ID: ..." with N, φ, Z, N_b, p and radii on stdout. An identical preparation
// already in the library is reused. Throws on input errors, a library of another material
// (db::MaterialMismatch) or a preparation that does not converge.
void prepare_command(const PrepareOptions& options);

}  // namespace grainbank::app
