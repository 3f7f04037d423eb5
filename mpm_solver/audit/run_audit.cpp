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

stats::ErrorSummary summary_of(const std::vector<StepComparison>& steps, bool (*selected)(StressSource)) {
  std::vector<double> errors;
  for (const StepComparison& c : steps)
    if (selected(c.source)) errors.push_back(c.relative_error);
  return stats::summarize(errors);
}

}  // namespace

RunAudit audit_run(const io::AuditTrail& trail, const std::function<ReferenceSlot(std::uint32_t)>& reference_of) {
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

  RunAudit audit;
  std::vector<double> live_norms;
  for (auto& steps : per_point)
    for (StepComparison& c : steps) {
      live_norms.push_back(stats::stress_norm(stress6(c.live)));
      audit.steps.push_back(c);
    }
  audit.stress_floor = live_norms.empty() ? 0.0 : 0.01 * stats::quantile(live_norms, 0.5);
  for (StepComparison& c : audit.steps)
    c.relative_error = stats::relative_stress_error(stress6(c.run), stress6(c.live), audit.stress_floor);

  audit.hit = summary_of(audit.steps, [](StressSource s) { return s == StressSource::hit; });
  audit.miss = summary_of(audit.steps, [](StressSource s) { return s == StressSource::miss; });
  audit.live = summary_of(audit.steps, [](StressSource s) { return s == StressSource::live; });
  audit.cached = summary_of(audit.steps, [](StressSource s) { return s == StressSource::hit || s == StressSource::miss; });
  audit.all = summary_of(audit.steps, [](StressSource) { return true; });
  return audit;
}

}  // namespace grainbank::mpm::audit
