// Determinism check of stored records (issue 7, audit (1)): a record is replayed from the last
// snapshot of its path before it (or from the path's template when there is none) along the path's
// stored spec, with the sampler's own driver (app::drive_along_path), and the replayed stress is
// compared with the stored one. The engine is deterministic and a snapshot restores a cell bit for
// bit, so a sound record is reproduced exactly; any difference means the stored data changed after
// the run (corruption) or the engine no longer behaves as the one that wrote the library.
#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "database/lookup/lookup_types.hpp"
#include "database/store/library.hpp"

namespace grainbank::audit {

struct ReplayCheck {
  lookup::RecordRef record;
  std::int64_t from_record = 0;  // the snapshot's record index it was replayed from; 0 = the template
  db::Stress6 stored{}, replayed{};
  // False for a path whose spec is not a sampler path (the live cell of an MPM run, enriched into the
  // library, mpm_solver/dem_laws/enrichment.hpp): its increments are not stored exactly, so it is
  // not checked (`error` says why) and not flagged.
  bool replayable = true;
  std::string error;  // why the replay failed or was not done; empty on success
};

// Checks `records` (each path's records in ascending order share one replay per snapshot). `stored`
// holds the committed records of every path in `records`. Store errors of the path rows propagate;
// a failed replay (engine error, unreadable snapshot, invalid spec) is reported in its checks' `error`.
std::vector<ReplayCheck> replay_records(db::Library& library, const std::vector<lookup::RecordRef>& records,
                                        const std::map<std::int64_t, std::vector<db::Record>>& stored);

}  // namespace grainbank::audit
