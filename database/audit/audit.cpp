#include "database/audit/audit.hpp"

#include <stdexcept>

namespace grainbank::audit {
namespace {

// Committed records of every done path: the indexed set, and the truth of every comparison.
std::map<std::int64_t, std::vector<db::Record>> done_records(db::Library& library) {
  std::map<std::int64_t, std::vector<db::Record>> out;
  for (const db::PathRow& row : library.catalogue().paths())
    if (row.status == db::PathStatus::done && row.record_count > 0) out[row.id] = library.records(row.id);
  return out;
}

double error_between(const dem::Mat3& answer, const db::Stress6& truth, double floor) {
  return relative_stress_error(db::to_stress6(answer), truth, floor);
}

}  // namespace

AuditReport run_audit(db::Library& library, const AuditOptions& options) {
  AuditReport report;
  report.options = options;
  report.sample = draw_sample(library.catalogue().paths(), options.sample);
  if (report.sample.paths.empty())
    throw std::invalid_argument(library.directory().string() +
                                ": nothing to audit: no done path with at least two records");
  const auto records = done_records(library);
  report.done_paths = records.size();
  for (const auto& [id, rows] : records) report.indexed_records += rows.size();

  const std::vector<LookupComparison> comparisons =
      compare_lookups(records, report.sample.paths, library.key_scales(), options.lookup);
  std::vector<double> norms;
  for (const LookupComparison& c : comparisons) norms.push_back(stress_norm(c.truth));
  report.stress_floor = norms.empty() ? 0 : 0.01 * quantile(norms, 0.5);

  std::vector<double> in_index, left_out;
  std::vector<DistanceError> by_distance;
  for (std::size_t i = 0; i < comparisons.size(); ++i) {
    const LookupComparison& c = comparisons[i];
    LookupResult r{c.record,
                   norms[i],
                   error_between(c.in_index.stress, c.truth, report.stress_floor),
                   c.left_out.distance,
                   error_between(c.left_out.stress, c.truth, report.stress_floor),
                   stress_norm(db::to_stress6(c.left_out.stress - db::from_stress6(c.truth))),
                   c.left_out.estimated_error};
    in_index.push_back(r.in_index_error);
    // A library of one done path has no other path to answer from: no leave-one-out answer.
    if (c.left_out.neighbours > 0) {
      left_out.push_back(r.error);
      by_distance.push_back({r.distance, r.error});
    }
    report.lookups.push_back(r);
  }
  report.in_index = summarize(in_index);
  report.leave_one_out = summarize(left_out);
  report.bins = bin_by_distance(by_distance);
  report.at_tolerance = hits_at(by_distance, options.lookup.tolerance);
  report.suggestion = suggest_tolerance(by_distance, report.bins, options.target);

  std::vector<double> replayed;
  for (const ReplayCheck& check : replay_records(library, report.sample.records, records)) {
    ReplayResult r{check, 0, check.replayable && !check.error.empty()};
    if (check.error.empty()) {
      r.relative_error = relative_stress_error(check.replayed, check.stored, report.stress_floor);
      r.flagged = !(r.relative_error <= options.replay_tolerance);
      replayed.push_back(r.relative_error);
    }
    report.flagged += r.flagged ? 1 : 0;
    report.not_replayable += check.replayable ? 0 : 1;
    report.replays.push_back(r);
  }
  report.determinism = summarize(replayed);
  return report;
}

}  // namespace grainbank::audit
