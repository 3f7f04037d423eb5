// Cell templates of a library (DESIGN.md, "Preparation"): the prepared cell every path starts from.
// A template is identified by the library's parameter hash and its preparation identity (the whole
// preparation spec including its seed, or the packing file's content hash and skin): preparing the
// same identity again returns the stored template instead of a second copy.
#pragma once
#include <cstdint>
#include <string>
#include <nlohmann/json.hpp>

#include "dem_sampler/driver/cell_input.hpp"
#include "database/store/library.hpp"

namespace grainbank::sampler {

// The numbers a user checks after preparing: N, φ, Z, N_b, p, radii.
struct TemplateSummary {
  std::int64_t id = 0;
  bool reused = false;  // an identical template was already stored
  std::size_t spheres = 0;
  double solid_fraction = 0, coordination = 0, pressure = 0;  // p = -tr σ / 3 [Pa]
  std::int64_t bonds = 0;
  double min_radius = 0, max_radius = 0, mean_radius = 0;  // [m]
};

// JSON that identifies how a template's cell was made (no results in it).
nlohmann::json preparation_identity(const app::CellInput& input);

// Stores the prepared cell of `input` in shard `shard_name` unless the library holds an identical one.
// The library must be built for input.material (MaterialMismatch otherwise). The caller holds the
// library's sampler lock (the shard gets one writer).
TemplateSummary prepare_template(db::Library& library, const std::string& shard_name, const app::CellInput& input,
                                 const dem::PreparationObserver& observer = {});

// Summary of a stored template (restored with the library's material).
TemplateSummary describe_template(db::Library& library, std::int64_t template_id);

}  // namespace grainbank::sampler
