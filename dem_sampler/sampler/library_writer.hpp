// The one door of a sampler process to its library: every catalogue and shard access behind one
// mutex, because the HDF5 C library is not thread-safe and the catalogue connection is shared. DEM
// work happens outside it; only reads of specs and templates and the commits of records wait here.
#pragma once
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "dem_sampler/sampler/path_plan.hpp"
#include "database/store/library.hpp"

namespace grainbank::sampler {

// What a path needs to run: its plan and the template cell it starts from (shared, read-only).
struct PathWork {
  std::int64_t path_id = 0;
  PathPlan plan;
  std::shared_ptr<const db::StoredCell> start;
};

class LibraryWriter {
 public:
  LibraryWriter(db::Library& library, db::ShardWriter& shard) : library_(library), shard_(shard) {}

  const dem::Material& material() const { return library_.material(); }
  db::KeyScales key_scales();

  // Reads the path's spec and template (each template read once) and marks the path running here.
  PathWork start(std::int64_t path_id);
  void append(std::int64_t path_id, const std::vector<db::Record>& records);
  void snapshot(std::int64_t path_id, std::int64_t record_index, const db::StoredCell& cell);
  void finish(std::int64_t path_id, db::PathStatus status, double wall_time, const std::string& error = {});
  // Back to pending (an abandoned path): its records are dropped and it will run again.
  void abandon(std::int64_t path_id);

  // Runs `f` under the mutex (observers that must not interleave with commits).
  template <class F>
  void locked(F&& f) {
    std::lock_guard lock(mutex_);
    f();
  }

 private:
  std::mutex mutex_;
  db::Library& library_;
  db::ShardWriter& shard_;
  std::map<std::int64_t, std::shared_ptr<const db::StoredCell>> templates_;
};

}  // namespace grainbank::sampler
