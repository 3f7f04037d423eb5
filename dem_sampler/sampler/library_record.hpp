// A path record of the driver turned into the library's record (database/store/record.hpp), with its
// state key as the lookup defines it (database/lookup/state_key.hpp), so the stored key column and
// the index agree.
#pragma once
#include "path_driver.hpp"
#include "store/key_definition.hpp"
#include "store/record.hpp"

namespace grainbank::sampler {

// `L` is the velocity gradient imposed over the increment that ended at this record (zero for the
// initial state).
db::Record to_library_record(const app::PathRecord& record, const dem::Mat3& L, const db::KeyScales& scales);

}  // namespace grainbank::sampler
