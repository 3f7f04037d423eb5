#include "database/store/prune.hpp"

#include <cmath>
#include <map>
#include <set>
#include <stdexcept>

#include "database/store/sampler_lock.hpp"
#include "database/store/shard.hpp"

namespace grainbank::db {

namespace {

std::uintmax_t shard_bytes(Library& library) {
  std::uintmax_t bytes = 0;
  for (const ShardRow& shard : library.catalogue().shards()) {
    const std::filesystem::path file = library.shard_path(shard);
    if (std::filesystem::exists(file)) bytes += std::filesystem::file_size(file);
  }
  return bytes;
}

}  // namespace

std::vector<std::int64_t> kept_snapshots(const std::vector<std::int64_t>& indices, std::int64_t keep_per_path) {
  const auto n = static_cast<std::int64_t>(indices.size());
  if (keep_per_path < 0) throw std::invalid_argument("keep_per_path: expected an integer >= 0");
  if (n <= keep_per_path) return indices;
  if (keep_per_path == 0) return {};
  if (keep_per_path == 1) return {indices.back()};
  std::set<std::int64_t> kept;
  for (std::int64_t i = 0; i < keep_per_path; ++i)
    kept.insert(indices[static_cast<std::size_t>(
        std::llround(static_cast<double>(i) * static_cast<double>(n - 1) / static_cast<double>(keep_per_path - 1)))]);
  return {kept.begin(), kept.end()};
}

PruneReport prune_snapshots(Library& library, std::int64_t keep_per_path, bool dry_run) {
  const SamplerLock lock(library.directory());
  PruneReport report;
  report.bytes_before = shard_bytes(library);
  std::map<std::int64_t, std::vector<SnapshotRow>> by_path;
  for (const SnapshotRow& row : library.catalogue().snapshots()) by_path[row.path_id].push_back(row);
  std::vector<std::int64_t> removed_ids;
  std::map<std::int64_t, std::set<std::string>> dropped_by_shard;
  for (auto& [path_id, rows] : by_path) {
    report.snapshots_before += static_cast<std::int64_t>(rows.size());
    const PathStatus status = library.catalogue().path(path_id).status;
    if (status != PathStatus::done && status != PathStatus::failed) continue;  // a writer may still add
    std::sort(rows.begin(), rows.end(), [](const auto& a, const auto& b) { return a.record_index < b.record_index; });
    std::vector<std::int64_t> indices;
    for (const SnapshotRow& row : rows) indices.push_back(row.record_index);
    const std::vector<std::int64_t> kept = kept_snapshots(indices, keep_per_path);
    for (const SnapshotRow& row : rows) {
      if (std::binary_search(kept.begin(), kept.end(), row.record_index)) continue;
      removed_ids.push_back(row.id);
      dropped_by_shard[row.shard_id].insert(Shard::snapshot_group(row.path_id, row.record_index));
    }
  }
  report.snapshots_removed = static_cast<std::int64_t>(removed_ids.size());
  for (const auto& [shard_id, groups] : dropped_by_shard) report.shards_rewritten.push_back(library.catalogue().shard(shard_id).file);
  if (dry_run || removed_ids.empty()) {
    report.bytes_after = report.bytes_before;
    return report;
  }
  library.catalogue().delete_snapshots(removed_ids);
  for (const auto& [shard_id, groups] : dropped_by_shard)
    Shard::rewrite_without(library.shard_path(library.catalogue().shard(shard_id)), {groups, {}});
  report.bytes_after = shard_bytes(library);
  return report;
}

}  // namespace grainbank::db
