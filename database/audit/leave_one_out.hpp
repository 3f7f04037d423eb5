// What the lookup answers for stored records (issue 7, audit (2)): each record of the audited paths
// is queried twice with its own state (F, L, damage), once in an index of every done path (the record
// itself is indexed: the answer is exact up to round-off, a check of the index) and once in an index
// without the record's own path (leave-one-path-out: the honest error of a state the library has
// not simulated, at the distance of its nearest other record). One index is built per audited path.
#pragma once
#include <cstdint>
#include <map>
#include <vector>

#include "database/lookup/lookup_index.hpp"

namespace grainbank::audit {

struct LookupComparison {
  lookup::RecordRef record;
  db::Stress6 truth{};            // the stored stress
  lookup::LookupAnswer in_index;  // from the index of every done path
  lookup::LookupAnswer left_out;  // from the index without the record's path
};

// `records`: the committed records of every done path, by path id (the indexed set). Compares every
// record but record 0 (the template's state, common to all paths of a template) of each of `paths`.
std::vector<LookupComparison> compare_lookups(const std::map<std::int64_t, std::vector<db::Record>>& records,
                                              const std::vector<std::int64_t>& paths, const db::KeyScales& scales,
                                              const lookup::LookupOptions& options);

}  // namespace grainbank::audit
