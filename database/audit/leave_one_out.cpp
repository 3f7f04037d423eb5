#include "database/audit/leave_one_out.hpp"

#include <memory>

namespace grainbank::audit {
namespace {

std::unique_ptr<lookup::LookupIndex> index_without(const std::map<std::int64_t, std::vector<db::Record>>& records,
                                                   std::int64_t left_out, const db::KeyScales& scales) {
  auto index = std::make_unique<lookup::LookupIndex>(scales);
  for (const auto& [path_id, rows] : records)
    if (path_id != left_out) index->insert(path_id, 0, rows);
  return index;
}

lookup::LookupState state_of(const db::Record& r) { return {r.F, r.L, r.damage}; }

}  // namespace

std::vector<LookupComparison> compare_lookups(const std::map<std::int64_t, std::vector<db::Record>>& records,
                                              const std::vector<std::int64_t>& paths, const db::KeyScales& scales,
                                              const lookup::LookupOptions& options) {
  // Path ids are positive, so -1 leaves nothing out.
  const std::unique_ptr<lookup::LookupIndex> full = index_without(records, -1, scales);
  std::vector<LookupComparison> out;
  for (const std::int64_t path_id : paths) {
    const std::unique_ptr<lookup::LookupIndex> others = index_without(records, path_id, scales);
    const std::vector<db::Record>& rows = records.at(path_id);
    for (std::size_t i = 1; i < rows.size(); ++i) {
      const lookup::LookupState state = state_of(rows[i]);
      out.push_back({{path_id, static_cast<std::int64_t>(i)},
                     rows[i].stress,
                     full->query(state, options),
                     others->query(state, options)});
    }
  }
  return out;
}

}  // namespace grainbank::audit
