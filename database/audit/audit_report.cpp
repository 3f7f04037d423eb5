#include "database/audit/audit_report.hpp"

#include <cmath>

namespace grainbank::audit {

using nlohmann::json;

json summary_of(const ErrorSummary& s) {
  return {{"count", s.count}, {"median", s.median}, {"p95", s.p95}, {"max", s.max}};
}

namespace {

// JSON has no infinity or NaN: those become null.
json number(double value) { return std::isfinite(value) ? json(value) : json(nullptr); }

json flagged_records(const AuditReport& report) {
  json out = json::array();
  for (const ReplayResult& r : report.replays) {
    if (!r.flagged) continue;
    json item = {{"path", r.check.record.path_id},
                 {"record", r.check.record.record_index},
                 {"from_record", r.check.from_record},
                 {"stored", r.check.stored}};
    if (r.check.error.empty()) {
      item["relative_error"] = number(r.relative_error);
      item["replayed"] = r.check.replayed;
    } else {
      item["error"] = r.check.error;
    }
    out.push_back(item);
  }
  return out;
}

json hits_json(const HitErrors& h) {
  return {{"tolerance", h.tolerance}, {"hit_share", h.hit_share}, {"hits", summary_of(h.hits)}};
}

json distance_json(const AuditReport& report) {
  json bins = json::array();
  for (const DistanceBin& b : report.bins)
    bins.push_back({{"distance_min", b.distance_min},
                    {"distance_max", b.distance_max},
                    {"count", b.error.count},
                    {"median", b.error.median},
                    {"p95", b.error.p95},
                    {"max", b.error.max}});
  return {{"bins", bins},
          {"target", report.options.target},
          {"suggested_tolerance", report.suggestion ? json(report.suggestion->tolerance) : json(nullptr)},
          {"at_suggested", report.suggestion ? hits_json(*report.suggestion) : json(nullptr)},
          {"at_tolerance", hits_json(report.at_tolerance)}};
}

}  // namespace

json summary_json(const AuditReport& report) {
  const AuditOptions& o = report.options;
  json paths = report.sample.paths;
  json determinism = summary_of(report.determinism);
  determinism["checked"] = report.replays.size() - report.not_replayable;
  determinism["flagged"] = report.flagged;
  determinism["not_replayable"] = report.not_replayable;
  determinism["flagged_records"] = flagged_records(report);
  json in_index = summary_of(report.in_index);
  return {{"options",
           {{"paths", o.sample.paths},
            {"samples", o.sample.records},
            {"seed", o.sample.seed},
            {"k", o.lookup.k},
            {"tolerance", o.lookup.tolerance},
            {"target", o.target},
            {"replay_tolerance", o.replay_tolerance}}},
          {"library", {{"done_paths", report.done_paths}, {"indexed_records", report.indexed_records}}},
          {"sample", {{"paths", paths}, {"records", report.sample.records.size()}}},
          {"error_definition", {{"relative_to", "max(|sigma_true|_F, floor)"}, {"floor_pa", report.stress_floor}}},
          {"determinism", determinism},
          {"in_index", in_index},
          {"leave_one_out", summary_of(report.leave_one_out)},
          {"error_vs_distance", distance_json(report)}};
}

void write_records_csv(const AuditReport& report, std::ostream& out) {
  out.precision(17);
  out << "check,path,record,distance,relative_error,absolute_error_pa,estimated_error_pa,stress_norm_pa\n";
  for (const ReplayResult& r : report.replays) {
    if (!r.check.error.empty()) continue;
    out << "replay," << r.check.record.path_id << ',' << r.check.record.record_index << ",," << r.relative_error
        << ",,," << stress_norm(r.check.stored) << '\n';
  }
  for (const LookupResult& r : report.lookups) {
    out << "in_index," << r.record.path_id << ',' << r.record.record_index << ",," << r.in_index_error << ",,,"
        << r.stress_norm << '\n';
    if (!std::isfinite(r.distance)) continue;
    out << "leave_one_out," << r.record.path_id << ',' << r.record.record_index << ',' << r.distance << ',' << r.error
        << ',' << r.absolute_error << ',' << r.estimated_error << ',' << r.stress_norm << '\n';
  }
}

}  // namespace grainbank::audit
