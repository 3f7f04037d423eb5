// The audit trail of a run (`"audit": {"points": N}` in the scene): for a sample of material points,
// every step's velocity gradient and time step (the increment F_inc = exp(Δt L) of the step) and
// the stress the run answered with, and where it came from (library hit, miss, live cell). With these,
// `mpm_solver audit RUN` re-runs a live DEM cell through each sampled point's own history and measures
// what the cache cost in stress at every cached point-step (audit/run_audit.hpp).
//
// File RUN/audit_trail.h5: attributes `start_time` [s] and `scene` (the scene file the run read);
// one group /points/<id> per sampled point with datasets `time` and `dt` (n), `velocity_gradient`
// (n × 4: L_xx, L_xy, L_yx, L_yy), `stress` (n × 4: σ_xx, σ_yy, σ_xy, σ_zz, tension-positive [Pa]) and
// `source` (n, the StressSource values of coupling_status.hpp).
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "mpm_solver/core/coupling_status.hpp"
#include "mpm_solver/core/solver.hpp"

namespace grainbank::mpm::io {

// Its name in the run's output folder.
inline constexpr const char* kAuditTrailFile = "audit_trail.h5";

struct TrailStep {
  double time = 0, dt = 0;  // end of the step, its length [s]
  Mat2 velocity_gradient = Mat2::Zero();
  PointStress stress;
  StressSource source = StressSource::analytic;
};

struct PointTrail {
  std::uint32_t id = 0;
  std::vector<TrailStep> steps;
};

struct AuditTrail {
  double start_time = 0;  // of the run: not 0 when it resumed from a restart
  std::string scene;
  std::vector<PointTrail> points;
};

// The increment of a step, as the solver builds it.
inline KinematicIncrement step_increment(const TrailStep& step) {
  return KinematicIncrement::of_velocity_gradient(step.velocity_gradient, step.dt);
}

// Records the sampled points after every step of a run.
class AuditTrailRecorder {
 public:
  // Throws std::invalid_argument when an id is not a point of the solver.
  AuditTrailRecorder(const Solver& solver, std::vector<std::uint32_t> ids, std::string scene);
  void record(const Solver& solver, double dt);
  const AuditTrail& trail() const { return trail_; }

 private:
  AuditTrail trail_;
  std::vector<std::int64_t> slot_of_id_;  // point id → index in trail_.points, or -1
};

// Throw db::StoreError naming the file (and for reads the missing or malformed dataset). A trail
// already in `file` is replaced (atomically: written beside, then renamed over).
void write_audit_trail(const std::filesystem::path& file, const AuditTrail& trail);
AuditTrail read_audit_trail(const std::filesystem::path& file);

// `count` point ids spread evenly over the points whose law is DEM-backed (live, cache, hybrid), in id
// order. Throws std::invalid_argument when count is 0 or exceeds the number of such points.
std::vector<std::uint32_t> spread_audit_points(const Solver& solver, std::size_t count);

}  // namespace grainbank::mpm::io
