#include "mpm_solver/dem_laws/library_link.hpp"

#include <algorithm>

#include "database/store/error.hpp"
#include "database/surrogate/reindex.hpp"

namespace grainbank::mpm {

namespace {
db::Library open_library(const std::filesystem::path& dir, const dem::Material* expected) {
  return expected ? db::Library::open(dir, *expected) : db::Library::open(dir);
}
}  // namespace

LibraryLink::LibraryLink(const std::filesystem::path& dir, std::int64_t template_id, const dem::Material* expected,
                         const std::optional<db::KeyScales>& scales)
    : library_(open_library(dir, expected)), template_id_(template_id) {
  template_cell_.emplace(library_.restore(library_.template_cell(template_id)));
  index_ = std::make_unique<lookup::LookupIndex>(scales ? *scales : library_.key_scales());
  index_->refresh(library_);
  for (const db::SnapshotRow& row : library_.catalogue().snapshots()) snapshots_[row.path_id].push_back(row.record_index);
  for (auto& [path, indices] : snapshots_) std::sort(indices.begin(), indices.end());
}

std::optional<db::StoredCell> LibraryLink::snapshot_before(const lookup::RecordRef& ref) {
  const auto found = snapshots_.find(ref.path_id);
  if (found == snapshots_.end()) return std::nullopt;
  const std::vector<std::int64_t>& indices = found->second;
  const auto after = std::upper_bound(indices.begin(), indices.end(), ref.record_index);
  if (after == indices.begin()) return std::nullopt;
  const std::int64_t record = *(after - 1);
  return locked([&](db::Library& library) { return library.snapshot_cell(ref.path_id, record); });
}

std::vector<StateSnapshot> LibraryLink::state_snapshots() {
  return locked([&](db::Library& library) {
    std::vector<StateSnapshot> out;
    for (const db::PathRow& path : library.catalogue().paths()) {
      const auto found = snapshots_.find(path.id);
      if (path.status != db::PathStatus::done || path.template_id != template_id_ || found == snapshots_.end()) continue;
      const std::vector<db::Record> records = library.records(path.id);
      for (const std::int64_t k : found->second) {
        if (k >= static_cast<std::int64_t>(records.size())) continue;  // not committed
        out.push_back({surrogate::point_state(records[static_cast<std::size_t>(k)]),
                       library.snapshot_cell(path.id, k).state});
      }
    }
    return out;
  });
}

}  // namespace grainbank::mpm
