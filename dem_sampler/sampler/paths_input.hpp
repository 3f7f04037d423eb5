// PATHS.json: the paths `dem_sampler sample` adds to a library. Explicit paths (segments as in
// PATH.json), replays (one in-plane L per record interval, e.g. the history of an MPM material point)
// generators (path_generator.hpp) and state probes (state_probes.hpp), with shared defaults. Schema
// in README.md ("paths.json").
// Reading is all-or-nothing and touches no library, so an invalid file changes nothing.
#pragma once
#include <filesystem>
#include <vector>

#include "dem_sampler/sampler/path_plan.hpp"

namespace grainbank::sampler {

// In file order: explicit and replay paths ("paths"), then each generator's paths ("generators"),
// then each probe set's ("probes").
// Throws common::InputError naming the file and the JSON path of the first problem.
std::vector<PathPlan> load_paths_file(const std::filesystem::path& file);

}  // namespace grainbank::sampler
