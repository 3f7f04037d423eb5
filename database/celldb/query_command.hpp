// `celldb query LIB --state JSON [--k N] [--tolerance T] [--json]`: the nearest-state answer of a
// library for one kinematic state, as the MPM would get it (lookup/lookup_index.hpp).
//
// The state is JSON text or a file holding it: {"F": [[..],[..]], "L": [[..],[..]], "D": 0.1} with
// F and L 2×2 (in-plane, z completed as F_zz = 1, L_zz = 0) or 3×3; L and D default to zero.
#pragma once
#include <filesystem>
#include <ostream>
#include <string>

#include <nlohmann/json.hpp>

#include "database/lookup/lookup_types.hpp"

namespace grainbank::celldb {

struct QueryOptions {
  std::filesystem::path library;
  std::string state;  // JSON text, or the name of a file holding it
  lookup::LookupOptions lookup;
  bool json = false;
};

// Throws std::invalid_argument naming `source` and the JSON path of a bad entry.
lookup::LookupState lookup_state_from_json(const nlohmann::json& json, const std::string& source);

nlohmann::json query_library(const QueryOptions& options);
int run_query(const QueryOptions& options, std::ostream& out);

}  // namespace grainbank::celldb
