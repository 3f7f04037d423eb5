// What the readers of the DEM-backed laws (live, cache, hybrid) share: the live-cell settings, the
// cell a material's points start from, and the check that a cell or library answers the physics the
// scene declares. Errors name the scene file and JSON pointer.
#pragma once
#include <filesystem>
#include <string>

#include "dem_sampler/cell/dem_cell.hpp"
#include "common/json_input.hpp"
#include "mpm_solver/dem_laws/live_cell_model.hpp"
#include "mpm_solver/laws/law_registry.hpp"

namespace grainbank::mpm {

// "substepping": {"q_t", "q_n", "q_sigma"} and "q_h" (seed Eqs. 3 and 4), and "retiling":
// {"max_spheres" (0 or absent: off), "beyond_cap": "stop" (default) | "regenerate"}, defaults where
// absent.
LiveDemSettings read_live_settings(const common::JsonNode& material);

// Exactly one of "cell" (a cell.json, prepared here) and "library" with "template" (loaded).
dem::DemCell read_cell_template(const common::JsonNode& material, const std::filesystem::path& folder);

// Refuses a cell or library built with other effects than the scene declares, and a substepping.q_t
// that its dashpots make unstable (dem::max_time_step_factor); `source` names it in the message
// ("the cell", "the library LIB").
void require_compatible(const common::JsonNode& material, const dem::Material& built, const DemEffects& scene,
                        const std::string& source, const LiveDemSettings& live);

}  // namespace grainbank::mpm
