// `celldb info LIB [--json]`: what a library holds (counts, sizes, material, key definition) and how
// much of the key space its done paths cover (lookup/key_coverage.hpp).
#pragma once
#include <filesystem>
#include <ostream>

#include <nlohmann/json.hpp>

namespace grainbank::celldb {

struct InfoOptions {
  std::filesystem::path library;
  bool json = false;
};

// The summary as JSON (also the --json output).
nlohmann::json library_info(const std::filesystem::path& library);

// Prints the summary; returns the exit code. Throws StoreError when the library cannot be opened.
int run_info(const InfoOptions& options, std::ostream& out);

}  // namespace grainbank::celldb
