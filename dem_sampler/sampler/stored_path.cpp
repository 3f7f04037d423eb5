#include "dem_sampler/sampler/stored_path.hpp"

#include <nlohmann/json.hpp>

#include "common/json_input.hpp"
#include "database/store/error.hpp"

namespace grainbank::sampler {

std::optional<PathPlan> stored_plan(db::Library& library, const db::PathRow& row) {
  const std::string path = "path " + std::to_string(row.id);
  nlohmann::json spec;
  try {
    spec = nlohmann::json::parse(row.spec);
  } catch (const nlohmann::json::exception& e) {
    throw db::StoreError(library.catalogue().file(), path + ": spec is not JSON: " + e.what());
  }
  if (!spec.is_object() || !spec.contains("segments")) return std::nullopt;
  return plan_from_json(common::JsonNode(spec, library.catalogue().file().string() + ": " + path + " spec"));
}

}  // namespace grainbank::sampler
