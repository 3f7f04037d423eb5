#include "mpm_solver/audit/run_audit.hpp"

#include <exception>
#include <stdexcept>
#include <string>

#include "database/store/record.hpp"

namespace grainbank::mpm::audit {

namespace stats = grainbank::audit;

namespace {

db::Stress6 stress6(const PointStress& s) {
  dem::Mat3 m = dem::Mat3::Zero();
  m.topLeftCorner<2, 2>() = s.in_plane;
  m(2, 2) = s.zz;
  return db::to_stress6(m);
}

// The comparisons of one point; throws with the point, step and time when its reference fails.
std::vector<StepComparison> rerun(const io::PointTrail& point, const ReferenceSlot& reference) {
  std::vector<StepComparison> steps;
  steps.reserve(point.steps.size());
  PointStress live;
  Mat2 F = Mat2::Identity();
  for (std::size_t k = 0; k < point.steps.size(); ++k) {
    const io::TrailStep& s = point.steps[k];
    try {
      const KinematicIncrement increment = io::step_increment(s);
      F = increment.F * F;
      reference.law->update(reference.slot, increment, F, live);
    } catch (const std::exception& e) {
      throw std::runtime_error("audit: the live cell of point " + std::to_string(point.id) + " failed at step " +
                               std::to_string(k) + " (t = " + std::to_string(s.time) + " s): " + e.what());
    }
    steps.push_back({point.id, k, s.time, s.source, s.stress, live, 0.0});
  }
  return steps;
}

// Every point re-run in its reference slot (points in parallel), its steps in order, point by point.
std::vector<StepComparison> rerun_all(const io::AuditTrail& trail,
                                      const std::function<ReferenceSlot(std::uint32_t)>& reference_of) {
  std::vector<ReferenceSlot> references;
  for (const io::PointTrail& p : trail.points) references.push_back(reference_of(p.id));

  const long n = static_cast<long>(trail.points.size());
  std::vector<std::vector<StepComparison>> per_point(trail.points.size());
  std::exception_ptr failure;
#pragma omp parallel for schedule(dynamic, 1)
  for (long i = 0; i < n; ++i) {
    try {
      per_point[i] = rerun(trail.points[i], references[i]);
    } catch (...) {
#pragma omp critical(run_audit_failure)
      if (!failure) failure = std::current_exception();
    }
  }
  if (failure) std::rethrow_exception(failure);
  std::vector<StepComparison> steps;
  for (auto& point : per_point) steps.insert(steps.end(), point.begin(), point.end());
  return steps;
}

bool is_hit(StressSource s) { return s == StressSource::hit; }
bool is_miss(StressSource s) { return s == StressSource::miss; }
bool is_live(StressSource s) { return s == StressSource::live; }
bool is_cached(StressSource s) { return s == StressSource::hit || s == StressSource::miss; }
bool is_any(StressSource) { return true; }

// The errors of the steps whose source is selected.
stats::ErrorSummary summary_of(const std::vector<StepComparison>& steps, const std::vector<double>& errors,
                               bool (*selected)(StressSource)) {
  std::vector<double> chosen;
  for (std::size_t i = 0; i < steps.size(); ++i)
    if (selected(steps[i].source)) chosen.push_back(errors[i]);
  return stats::summarize(chosen);
}

// `errors`, parallel to `steps`, summarized by each step's source.
SourceSummaries by_source(const std::vector<StepComparison>& steps, const std::vector<double>& errors) {
  return {summary_of(steps, errors, is_hit), summary_of(steps, errors, is_miss), summary_of(steps, errors, is_live),
          summary_of(steps, errors, is_cached), summary_of(steps, errors, is_any)};
}

}  // namespace

RunAudit audit_run(const io::AuditTrail& trail, const std::function<ReferenceSlot(std::uint32_t)>& reference_of) {
  RunAudit audit;
  audit.steps = rerun_all(trail, reference_of);
  std::vector<double> live_norms;
  for (const StepComparison& c : audit.steps) live_norms.push_back(stats::stress_norm(stress6(c.live)));
  audit.stress_floor = live_norms.empty() ? 0.0 : 0.01 * stats::quantile(live_norms, 0.5);
  std::vector<double> errors;
  for (StepComparison& c : audit.steps) {
    c.relative_error = stats::relative_stress_error(stress6(c.run), stress6(c.live), audit.stress_floor);
    errors.push_back(c.relative_error);
  }
  audit.errors = by_source(audit.steps, errors);
  return audit;
}

NoiseFloor noise_floor(const io::AuditTrail& trail, const RunAudit& audit,
                       const std::function<ReferenceSlot(std::uint32_t)>& other_of) {
  const std::vector<StepComparison> other = rerun_all(trail, other_of);
  NoiseFloor floor;
  for (std::size_t i = 0; i < other.size(); ++i) {
    floor.other.push_back(other[i].live);
    floor.relative_error.push_back(
        stats::relative_stress_error(stress6(other[i].live), stress6(audit.steps[i].live), audit.stress_floor));
  }
  floor.errors = by_source(audit.steps, floor.relative_error);
  return floor;
}

}  // namespace grainbank::mpm::audit
