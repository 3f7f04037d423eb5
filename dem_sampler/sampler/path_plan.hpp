// One path of a library as the sampler runs it: the driven path (segments of constant in-plane L with
// durations, record interval, substepping) and how often the full cell is snapshotted. Its canonical
// JSON is what the catalogue stores as the path's spec: every duration explicit (strain targets and
// replays already converted), numbers written to round-trip exactly, so equal specs mean equal runs.
#pragma once
#include <nlohmann/json.hpp>
#include <string>

#include "common/json_input.hpp"
#include "dem_sampler/driver/path_input.hpp"

namespace grainbank::sampler {

struct PathPlan {
  app::PathSpec path;
  long snapshot_interval = 0;  // K: a snapshot after every K-th record; 0 = none
};

// {"segments": [{"L": [[..],[..]], "duration": d}, ...], "record_interval": .., "snapshot_interval": ..,
//  "substepping": {"q_t": .., "q_n": .., "q_sigma": ..}}
nlohmann::json to_json(const PathPlan& plan);

// Reads the canonical form (a stored spec). Throws common::InputError naming `node`'s file and pointer.
PathPlan plan_from_json(const common::JsonNode& node);

// Records a path produces: the initial state and one per increment.
long record_count(const PathPlan& plan);

}  // namespace grainbank::sampler
