#include "database/lookup/key_coverage.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "database/lookup/state_key.hpp"

namespace grainbank::lookup {

KeyCoverage key_coverage(db::Library& library) {
  const db::KeyScales scales = library.key_scales();
  KeyCoverage coverage;
  coverage.min.fill(INFINITY);
  coverage.max.fill(-INFINITY);
  std::set<std::array<std::int64_t, db::kKeySize>> cells;
  for (const db::PathRow& path : library.catalogue().paths()) {
    if (path.status != db::PathStatus::done || path.record_count == 0) continue;
    for (const db::Record& record : library.records(path.id)) {
      const db::StateKey key = state_key(record, scales);
      std::array<std::int64_t, db::kKeySize> cell;
      for (std::size_t c = 0; c < db::kKeySize; ++c) {
        coverage.min[c] = std::min(coverage.min[c], key[c]);
        coverage.max[c] = std::max(coverage.max[c], key[c]);
        cell[c] = static_cast<std::int64_t>(std::floor(key[c]));
      }
      cells.insert(cell);
      ++coverage.records;
    }
  }
  if (coverage.records == 0) {
    coverage.min.fill(0);
    coverage.max.fill(0);
  }
  coverage.occupied_cells = static_cast<std::int64_t>(cells.size());
  return coverage;
}

}  // namespace grainbank::lookup
