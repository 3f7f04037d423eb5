// Live responses of a run written back to the library (DESIGN.md, "Fallback"): every live cell of a
// hybrid point becomes a new path of the run's own shard, so `celldb merge` and the next run's
// lookups see it.
//
// Promises:
// - One writer per shard: the shard is new and named after the run ("run-<UTC time>-<pid>"), never
//   another writer's; the run holds LIB/sampler.lock while it writes, so no sampler starts writers
//   on the library meanwhile (nor declares this run's running paths stale). A sampler holding the
//   lock makes the constructor throw db::StoreError naming the holder.
// - A path is registered and started when its point turns live, gets one record per MPM step of
//   its live cell (committed every kCommitBatch records and at each snapshot, in the store's usual
//   commit order) and a snapshot every `snapshot_interval` records while the run has written fewer
//   than `snapshot_budget` snapshots in all (issue 13: enrichment must not fill the disk; snapshots
//   are what fills it, records are small), and becomes `done` when its
//   point returns to the cache or the run finishes. A crash leaves it `running` (merge skips it)
//   until the next writer takes the lock: then it becomes `done` with its committed records
//   (db::reset_running_paths).
// - Thread-safe: the library is only touched through LibraryLink::locked.
#pragma once
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "mpm_solver/dem_laws/library_link.hpp"
#include "database/store/sampler_lock.hpp"

namespace grainbank::mpm {

// One live point's path while it is being written (held by the point, touched by its thread only).
struct RunPath {
  std::int64_t id = -1;
  std::vector<db::Record> pending;  // not committed yet
  std::int64_t records = 0;         // added so far
  std::chrono::steady_clock::time_point start;
  bool open() const { return id >= 0; }
};

class Enrichment {
 public:
  static constexpr std::size_t kCommitBatch = 32;

  static constexpr long kUnlimited = -1;
  // `lead`: this writer holds LIB/sampler.lock and declares stale `running` paths done; in a run
  // spread over MPI ranks rank 0 leads and each other rank writes its own shard beside it.
  Enrichment(LibraryLink& link, int snapshot_interval, long snapshot_budget = kUnlimited, bool lead = true);
  long snapshots_written() const { return snapshots_written_; }
  const std::string& shard_name() const { return shard_name_; }

  // Registers and starts a path on the link's template; `origin` says where its cell came from.
  RunPath start(const nlohmann::json& origin);
  // The cell's state after an increment at velocity gradient L that ended with regressed `stress`.
  void add(RunPath& path, const dem::DemCell& cell, const dem::Mat3& L, const dem::Mat3& stress);
  // Commits what is pending and marks the path done.
  void finish(RunPath& path);

 private:
  void commit(RunPath& path);

  LibraryLink& link_;
  int snapshot_interval_;
  long snapshot_budget_;
  long snapshots_written_ = 0;  // under the link's lock
  std::string shard_name_;
  std::optional<db::SamplerLock> lock_;
  std::unique_ptr<db::ShardWriter> writer_;
  std::int64_t started_ = 0;
};

}  // namespace grainbank::mpm
