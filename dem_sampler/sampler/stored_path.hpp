// A path read back from the catalogue: its stored spec turned into the plan the sampler runs (and
// `celldb audit` replays). Errors name the catalogue file and the path.
#pragma once
#include <optional>

#include "dem_sampler/sampler/path_plan.hpp"
#include "database/store/library.hpp"

namespace grainbank::sampler {

// The plan of `row`; none when its spec is not a sampler path (no "segments": the live cell of an
// MPM run). Throws db::StoreError when the spec is not JSON, common::InputError naming the catalogue,
// the path and the JSON pointer when it is not a valid plan.
std::optional<PathPlan> stored_plan(db::Library& library, const db::PathRow& row);

}  // namespace grainbank::sampler
