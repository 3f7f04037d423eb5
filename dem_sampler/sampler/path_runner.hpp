// Runs one path of a library from its template: a private deep copy of the template cell, driven
// along the path's segments; a record per record interval, committed in batches, and a snapshot after
// every K-th record. Nothing is shared with other paths, so the records do not depend on which thread,
// process or machine runs the path.
//
// Outcomes: done; failed (the engine threw or the cell diverged: the error text is stored and the
// committed records are kept for inspection); abandoned (stop requested: the path goes back to
// pending). Store errors are not path failures: they propagate.
#pragma once
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>

#include "dem_sampler/sampler/library_writer.hpp"

namespace grainbank::sampler {

enum class PathResult { done, failed, abandoned };

struct PathOutcome {
  std::int64_t path_id = 0;
  PathResult result = PathResult::done;
  long records = 0;         // committed by this run
  long dem_steps = 0;       // DEM steps taken
  std::size_t spheres = 0;
  double wall_time = 0;     // [s]
  std::string error;        // failed only
};

struct RunnerOptions {
  long commit_batch = 32;  // records per commit when no snapshot comes first
  const std::atomic<bool>* stop = nullptr;  // checked after every record
  // Called with the number of records of each commit, under the writer's lock.
  std::function<void(long)> on_commit;
};

PathOutcome run_path(LibraryWriter& writer, std::int64_t path_id, const db::KeyScales& scales,
                     const RunnerOptions& options);

}  // namespace grainbank::sampler
