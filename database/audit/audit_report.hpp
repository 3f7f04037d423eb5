// The audit's outputs as files: the JSON summary (what `celldb audit --json` prints, what the
// catalogue's audits row holds, what workflows/audit/plot_audit.py reads for the bins) and the CSV of
// every compared record (the histograms and the error-vs-distance scatter of the plots).
#pragma once
#include <nlohmann/json.hpp>
#include <ostream>

#include "database/audit/audit.hpp"

namespace grainbank::audit {

// {count, median, p95, max} of a sample of errors (the shape of every summary in the audits' JSON).
nlohmann::json summary_of(const ErrorSummary& summary);

// {"sample": {...}, "determinism": {checked, flagged, median, p95, max, flagged_records: [{path,
// record, from_record, relative_error, stored, replayed, error}]}, "in_index": {...}, "leave_one_out":
// {...}, "error_vs_distance": {bins: [...], target, suggested_tolerance, at_suggested, at_tolerance}}
// where at_* = {tolerance, hit_share, hits: {count, median, p95, max}}.
nlohmann::json summary_json(const AuditReport& report);

// Columns: check (replay | in_index | leave_one_out), path, record, distance (key units; empty for a
// replay and for in_index), relative_error, absolute_error_pa and estimated_error_pa (the lookup's own
// estimate; both leave_one_out only), stress_norm_pa.
void write_records_csv(const AuditReport& report, std::ostream& out);

}  // namespace grainbank::audit
