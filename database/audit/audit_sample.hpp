// Which paths and records an audit looks at: a seeded, reproducible choice (the same library, counts
// and seed give the same choice on every machine: std::mt19937_64 is fully specified and the draws
// use plain modulo). Paths are drawn first because each audited path costs one lookup index built
// without it; records are then drawn among the records of those paths.
#pragma once
#include <cstdint>
#include <vector>

#include "database/lookup/lookup_types.hpp"
#include "database/store/catalogue.hpp"

namespace grainbank::audit {

struct SampleSpec {
  std::size_t paths = 8;     // at most this many done paths
  std::size_t records = 16;  // at most this many records among them
  std::uint64_t seed = 1;
};

struct AuditSample {
  std::vector<std::int64_t> paths;         // ascending ids
  std::vector<lookup::RecordRef> records;  // ascending (path, record)
};

// Candidates are the `done` paths with at least two committed records; record 0 (the template's
// state, shared by every path of the template) is never drawn: no increment produced it.
AuditSample draw_sample(const std::vector<db::PathRow>& paths, const SampleSpec& spec);

}  // namespace grainbank::audit
