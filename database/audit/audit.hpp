// `celldb audit`: how far a library's answers can be trusted (issue 7). On a seeded sample of done
// paths and records it measures
//   (1) determinism: sampled records replayed from their preceding snapshot (replay_check.hpp) must
//       reproduce the stored stress; a record that does not is flagged with its path and index;
//   (2) the honest cache error: every record of the sampled paths queried in an index without its own
//       path (leave_one_out.hpp), next to the in-index answer (exact up to round-off);
//   (3) error against nearest distance: the leave-one-out errors binned by nearest-record distance,
//       and the lookup tolerance whose hits stay within a target error (error_statistics.hpp).
// Errors are relative: ‖σ_answer − σ_true‖_F / max(‖σ_true‖_F, floor) with the floor 1 % of the
// median ‖σ‖ of the audited records. The audit reads the library and writes nothing.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "database/audit/audit_sample.hpp"
#include "database/audit/error_statistics.hpp"
#include "database/audit/leave_one_out.hpp"
#include "database/audit/replay_check.hpp"

namespace grainbank::audit {

struct AuditOptions {
  SampleSpec sample;
  lookup::LookupOptions lookup;    // k of the queries; the tolerance whose hits are reported
  double target = 0.05;            // relative error the suggested tolerance must keep (p95 of hits)
  double replay_tolerance = 1e-9;  // a replayed stress further than this (relative) is flagged
};

struct ReplayResult {
  ReplayCheck check;
  double relative_error = 0;  // meaningless when check.error is set
  bool flagged = false;       // relative error above the replay tolerance, or a replayable record failed
};

struct LookupResult {
  lookup::RecordRef record;
  double stress_norm = 0;      // ‖σ_true‖_F [Pa]
  double in_index_error = 0;   // relative
  double distance = 0;         // leave-one-out nearest distance [key units]
  double error = 0;            // leave-one-out relative error
  double absolute_error = 0;   // leave-one-out ‖σ_answer − σ_true‖_F [Pa]
  double estimated_error = 0;  // the lookup's own estimate for that answer [Pa]
};

struct AuditReport {
  AuditOptions options;
  std::size_t done_paths = 0, indexed_records = 0;
  AuditSample sample;
  double stress_floor = 0;  // [Pa]
  std::vector<ReplayResult> replays;
  std::vector<LookupResult> lookups;
  ErrorSummary determinism, in_index, leave_one_out;  // determinism: successful replays only
  std::size_t flagged = 0;
  std::size_t not_replayable = 0;  // sampled records of paths that are not sampler paths (not checked)
  std::vector<DistanceBin> bins;
  HitErrors at_tolerance;               // hits at options.lookup.tolerance
  std::optional<HitErrors> suggestion;  // the tolerance that keeps options.target
};

// Throws StoreError when the library cannot be read, std::invalid_argument when it has no done path
// with at least two records.
AuditReport run_audit(db::Library& library, const AuditOptions& options);

}  // namespace grainbank::audit
