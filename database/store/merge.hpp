// Merging the responses computed elsewhere (other runs, MPI ranks, MPM runs' live cells) into a
// library (`celldb merge`).
//
// Promises:
// - The source is another library directory, or one shard file inside one (LIB2/shards/x.h5): what
//   is committed is only known from its catalogue, so a bare shard file is refused.
// - A source built for other physics (parameter hash) is refused with MaterialMismatch naming the
//   differing parameters; nothing is written.
// - What is merged: every `done` path (spec, committed records, snapshots, wall time) and the
//   templates of the source shard and of those paths. Pending, running and failed paths are skipped.
// - Each source shard lands in one new shard of the target, "merge-<source id>-<shard name>", written
//   through ShardWriter: the usual commit order, one writer per file (a concurrent second merge of
//   the same source fails on the HDF5 file lock instead of writing the same file).
// - Idempotent: merging the same source again adds nothing; a merge interrupted by a crash is
//   completed by running it again (a path it left running is marked failed and merged anew).
//   Templates are recognised by their origin, so one merged through several hops is stored once.
#pragma once
#include <cstdint>
#include <filesystem>

#include "database/store/library.hpp"

namespace grainbank::db {

struct MergeReport {
  std::int64_t shards = 0;         // source shards examined
  std::int64_t templates = 0;      // templates added to the target
  std::int64_t paths = 0;          // done paths added
  std::int64_t records = 0;        // records of those paths
  std::int64_t snapshots = 0;      // snapshots of those paths
  std::int64_t already_merged = 0; // done paths found in the target from an earlier merge
  std::int64_t skipped = 0;        // source paths not done
};

MergeReport merge_into(Library& target, const std::filesystem::path& source);

}  // namespace grainbank::db
