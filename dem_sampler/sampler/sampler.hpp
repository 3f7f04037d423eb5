// Runs the paths a WorkSource hands out, on a pool of threads in this process, writing through one
// LibraryWriter. One path per thread at a time; results do not depend on the number of threads.
// Stops taking new paths when `stop` is set; paths in progress are then abandoned (back to pending).
// A path that fails is recorded as failed and the others go on; a store error stops every thread,
// puts the paths in progress back to pending and is rethrown.
#pragma once
#include <atomic>
#include <functional>

#include "dem_sampler/sampler/path_runner.hpp"
#include "dem_sampler/sampler/work_source.hpp"

namespace grainbank::sampler {

struct SampleOptions {
  int threads = 1;
  long commit_batch = 32;
  const std::atomic<bool>* stop = nullptr;
};

// Observers are called under the writer's lock, so they never run concurrently.
struct SampleObserver {
  std::function<void(long records)> on_commit;
  std::function<void(const PathOutcome&)> on_path;
};

struct SampleSummary {
  long done = 0, failed = 0, abandoned = 0;
  long records = 0;
  long dem_steps = 0;       // of done paths
  double particle_steps = 0;  // Σ DEM steps × spheres, of done paths
  double seconds = 0;       // wall time of the whole run
};

SampleSummary run_paths(LibraryWriter& writer, WorkSource& source, const SampleOptions& options,
                        const SampleObserver& observer = {});

}  // namespace grainbank::sampler
