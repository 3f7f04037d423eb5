// `celldb prune`: a library's snapshots cut down to a budget per path (issue 13: libraries must not
// fill the disk; snapshots, full cell states, are most of their bytes). Templates and committed
// records are never touched, so every lookup answer stays the same; only warm starts have fewer
// cells to start from.
//
// Promises:
// - Each done or failed path keeps at most `keep_per_path` snapshots: with n > N of them, the first
//   and the last and N − 2 spread evenly between (record indices at round(i (n−1)/(N−1))); N = 1 keeps
//   the last (the state furthest along the path), N = 0 none. The choice depends only on the
//   catalogue, so a second prune with the same N removes nothing.
// - Order (SCHEMA.md, "Commit order and recovery"): the rows go first, in one transaction, so that
//   no reader can follow a row to a removed group; then each shard that held a removed snapshot is
//   rewritten without those groups (Shard::rewrite_without: a copy renamed over the file), which gives
//   the space back. A crash between the two leaves orphans that `celldb verify --repair` removes;
//   the library stays readable throughout.
// - Holds LIB/sampler.lock while it works: refused (db::StoreError naming the holder) while a sampler
//   or an enriching run writes the library.
// - A dry run computes the same report and changes nothing.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "database/store/library.hpp"

namespace grainbank::db {

struct PruneReport {
  std::int64_t snapshots_before = 0, snapshots_removed = 0;
  std::vector<std::string> shards_rewritten;  // files, relative to the library
  std::uintmax_t bytes_before = 0, bytes_after = 0;  // of the shard files
};

// The record indices of the snapshots a path keeps out of `indices` (sorted ascending).
std::vector<std::int64_t> kept_snapshots(const std::vector<std::int64_t>& indices, std::int64_t keep_per_path);

PruneReport prune_snapshots(Library& library, std::int64_t keep_per_path, bool dry_run);

}  // namespace grainbank::db
