#include "dem_sampler/driver/path_driver.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "dem_sampler/cell/effective_medium.hpp"
#include "dem_sampler/cell/matrix_functions.hpp"

namespace grainbank::app {
namespace {

// Relative slack so that a duration that is a multiple of Δt up to round-off gives no sliver step.
constexpr double kSlack = 1e-9;

long segment_increments(const PathSegment& s, double dt) {
  return std::max(1L, static_cast<long>(std::ceil(s.duration / dt * (1 - kSlack))));
}

PathRecord record_of(const dem::DemCell& cell, long index, const dem::Mat3& L, long substeps, const dem::Mat3& stress) {
  PathRecord r;
  r.index = index;
  r.time = cell.time();
  r.F = cell.deformation_gradient();
  r.L = L;
  r.substeps = substeps;
  r.stress = stress;
  r.measures = cell.measures();
  return r;
}

// The servo of a pressure-controlled segment: each increment's gradient is L plus an in-plane
// isotropic stretching α·diag(1, 1, 0), with
//   α_k = clip((1 − λ) α_{k−1} + c (p − P) / (2 K Δt), ±|sym L|)
// p = −tr σ/3 of the cell's last measured stress, K its Voigt bulk modulus (effective_medium.hpp) at
// its φ and Z. The increment's volumetric strain 2αΔt takes back the fraction c of the pressure
// error, and α keeps what earlier increments needed (an integral action, leaky by λ so that it
// settles): a dilatant packing sheared at a fixed pressure needs a steady opening, which a
// proportional servo would hold only at a pressure offset. With r = (true K)/K ≤ 1 (Voigt bounds it),
// the error obeys z² − (2 − λ − rc) z + (1 − λ) = 0, stable for every rc < 4 − 2λ. The clip keeps the
// cell from opening or closing faster than it shears; at steady isochoric flow (the critical state)
// α → 0 at p = P.
constexpr double kCorrected = 0.5;  // c
constexpr double kLeak = 0.1;       // λ
// A loose cell (few contacts, K → 0) jams within a small volume change: the gain takes at least the
// stiffness of a frictional packing at its isostatic coordination, Z = 4, or one increment closing a
// loose cell would overshoot the target many times over.
constexpr double kJammedCoordination = 4;

// The next increment's gradient of `segment`; `alpha` carries α from increment to increment.
dem::Mat3 controlled_gradient(const PathSegment& segment, const dem::DemCell& cell, double dt, double& alpha) {
  if (segment.pressure <= 0) return segment.L;
  const dem::CellMeasures m = cell.measures();
  const std::vector<double>& radius = cell.radii();
  const double mean_radius = std::accumulate(radius.begin(), radius.end(), 0.0) / static_cast<double>(radius.size());
  const dem::Material& material = cell.material();
  const double bulk = dem::voigt_moduli(m.solid_fraction, std::max(m.coordination, kJammedCoordination), mean_radius,
                                        material.contact.k_n, material.contact.k_t)
                          .bulk;
  const double rate = strain_rate_norm(segment.L);
  const double error = -cell.stress().trace() / 3 - segment.pressure;
  alpha = std::clamp((1 - kLeak) * alpha + kCorrected * error / (2 * bulk * dt), -rate, rate);
  dem::Mat3 L = segment.L;
  L(0, 0) += alpha;
  L(1, 1) += alpha;
  return L;
}

}  // namespace

long increment_count(const PathSpec& path) {
  long n = 0;
  for (const PathSegment& s : path.segments) n += segment_increments(s, path.record_interval);
  return n;
}

void drive_along_path(dem::DemCell& cell, const PathSpec& path,
                      const std::function<void(const PathRecord&)>& on_record, long from_record,
                      const dem::Mat3& resumed_gradient) {
  long index = 0;
  if (from_record == 0) on_record(record_of(cell, index, dem::Mat3::Zero(), 0, cell.measures().stress));
  for (const PathSegment& segment : path.segments) {
    const long n = segment_increments(segment, path.record_interval);
    const dem::Mat3 full_increment = dem::matrix_exponential(segment.L * path.record_interval);
    double alpha = 0;  // the pressure servo's isotropic stretching, carried over the segment
    for (long k = 1; k <= n; ++k) {
      if (index < from_record) {  // already in the cell we resume from
        if (++index == from_record) alpha = resumed_gradient(0, 0) - segment.L(0, 0);
        continue;
      }
      const double dt =
          k < n ? path.record_interval : segment.duration - static_cast<double>(n - 1) * path.record_interval;
      const dem::Mat3 L = controlled_gradient(segment, cell, dt, alpha);
      const dem::Mat3 increment =
          k < n && segment.pressure <= 0 ? full_increment : dem::matrix_exponential(L * dt);
      const dem::IncrementResult result = cell.advance(increment, dt, path.substepping);
      on_record(record_of(cell, ++index, L, result.substeps, result.stress));
    }
  }
}

}  // namespace grainbank::app
