// The audit of an MPM run (`mpm_solver audit RUN`, issue 7): how far the stresses a run answered were
// from what live DEM cells would have answered. Every point of the run's audit trail
// (io/audit_trail.hpp) is re-run from its template through its own recorded increments by the live
// law of its material (the reference), and at every step the stress the run answered is compared
// with the reference's:
//   relative error = ‖σ_run − σ_live‖_F / max(‖σ_live‖_F, floor), floor = 1 % of the median ‖σ_live‖
// (the definition of the library audit, audit/error_statistics.hpp). The reference feels the point's
// kinematics but not its own stress (no two-way coupling), so this is the error of the answer for
// the history the run took.
// Steps are summarized by their source: a library hit, a miss, a live cell of a hybrid point (which
// started from a warm start, not from the point's own history), and the cached ones (hit or miss).
// A run of the live law itself replays bit for bit: every error is 0.
#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include "database/audit/error_statistics.hpp"
#include "mpm_solver/core/constitutive_law.hpp"
#include "mpm_solver/io/audit_trail.hpp"

namespace grainbank::mpm::audit {

struct StepComparison {
  std::uint32_t point = 0;
  std::size_t step = 0;  // index in the point's trail
  double time = 0;
  StressSource source = StressSource::live;
  PointStress run, live;
  double relative_error = 0;
};

// Error summaries of point-steps by what answered the run: a hit, a miss, a live cell, cached (hit or
// miss) and all.
struct SourceSummaries {
  grainbank::audit::ErrorSummary hit, miss, live, cached, all;
};

struct RunAudit {
  std::vector<StepComparison> steps;  // point by point, in step order
  double stress_floor = 0;            // [Pa]
  SourceSummaries errors;
};

// A live law and a slot of it at the template state that nothing else uses: where a point is re-run.
struct ReferenceSlot {
  ConstitutiveLaw* law = nullptr;
  std::size_t slot = 0;
};

// Re-runs every point of `trail` in its reference slot (points in parallel) and compares. Throws
// std::runtime_error naming the point, step and time when a reference cell fails.
RunAudit audit_run(const io::AuditTrail& trail, const std::function<ReferenceSlot(std::uint32_t)>& reference_of);

// The audit's noise floor: what two live cells of one recipe differ by along the same histories.
// Every point of `trail` is re-run a second time by a live cell of another packing (`other_of`, the
// same material and size prepared with another seed), and at every step that cell's stress is
// compared with the first reference's by the formula and stress floor of `audit`. A run whose errors
// are at this floor is as close to its reference as another packing of the same cell is.
struct NoiseFloor {
  std::vector<PointStress> other;      // the other packing's stress, parallel to audit.steps
  std::vector<double> relative_error;  // ‖σ_other − σ_live‖_F / max(‖σ_live‖_F, audit.stress_floor)
  SourceSummaries errors;              // by the source of the run's step
};

NoiseFloor noise_floor(const io::AuditTrail& trail, const RunAudit& audit,
                       const std::function<ReferenceSlot(std::uint32_t)>& other_of);

}  // namespace grainbank::mpm::audit
