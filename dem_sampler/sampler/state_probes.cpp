#include "dem_sampler/sampler/state_probes.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace grainbank::sampler {

const double kMaxPlaneStrainPsi = std::atan(std::sqrt(6.0));

namespace {

constexpr double kRootHalf = std::numbers::sqrt2 / 2;

void check(const ProbeSpec& s) {
  const auto fail = [](const std::string& what) { throw std::invalid_argument("probes: " + what); };
  const auto all_positive = [](const std::vector<double>& v) {
    for (double x : v)
      if (!(x > 0) || !std::isfinite(x)) return false;
    return !v.empty();
  };
  if (s.bases.empty()) fail("bases: expected a non-empty array");
  if (!all_positive(s.depths)) fail("depths: expected a non-empty array of positive strains");
  if (!(s.base_rate > 0) || !std::isfinite(s.base_rate)) fail("base_rate: expected a positive rate [1/s]");
  for (ProbeBase base : s.bases)
    if (base == ProbeBase::held_shear && (!(s.base_pressure > 0) || !std::isfinite(s.base_pressure)))
      fail("base_pressure: expected a positive mean pressure [Pa] for the held_shear base");
  if (s.psi.empty()) fail("psi: expected a non-empty array of angles");
  for (double psi : s.psi)
    if (!(std::abs(psi) <= kMaxPlaneStrainPsi + 1e-12))
      fail("psi: expected angles within ±67.79° (atan √6: in-plane isotropic loading is the most plane strain allows)");
  if (s.beta.empty()) fail("beta: expected a non-empty array of angles");
  for (double beta : s.beta)
    if (!std::isfinite(beta)) fail("beta: expected finite angles");
  if (!all_positive(s.rates)) fail("rates: expected a non-empty array of positive rates [1/s]");
  if (!(s.probe_strain > 0) || !std::isfinite(s.probe_strain)) fail("probe_strain: expected a positive strain");
  if (!(s.record_interval > 0)) fail("record_interval: expected a positive time [s]");
}

dem::Mat3 base_gradient(ProbeBase base, double rate) {
  dem::Mat3 L = dem::Mat3::Zero();
  switch (base) {
    case ProbeBase::compression: L(0, 0) = L(1, 1) = -kRootHalf * rate; break;
    case ProbeBase::extension: L(0, 0) = L(1, 1) = kRootHalf * rate; break;
    case ProbeBase::shear:
    case ProbeBase::held_shear: L(0, 1) = std::numbers::sqrt2 * rate; break;
    case ProbeBase::oedometric: L(1, 1) = -rate; break;
  }
  return L;
}

// The least compressive in-plane principal stress axis the base leaves: simple shear's stretching
// axis, x for oedometric compression along y; none for the in-plane isotropic bases (then every β is
// the same probe, see the header).
bool is_shear(ProbeBase base) { return base == ProbeBase::shear || base == ProbeBase::held_shear; }
double base_axis(ProbeBase base) { return is_shear(base) ? std::numbers::pi / 4 : 0.0; }
bool has_stress_axes(ProbeBase base) { return is_shear(base) || base == ProbeBase::oedometric; }

}  // namespace

dem::Mat3 probe_direction(double psi, double axis_angle, double rate) {
  // b = 1 unless ψ is at the plane-strain limit, where the probe is in-plane isotropic (b = 0).
  const double t = std::tan(psi);
  const double limit = 6 - 1e-12;
  double a = 1, b = 0;
  if (t * t < limit) {
    a = std::copysign(std::sqrt(t * t / (2 - t * t / 3)), psi);
    b = 1;
  } else {
    a = psi > 0 ? 1 : -1;
  }
  const double c = std::cos(2 * axis_angle), s = std::sin(2 * axis_angle);
  dem::Mat3 D = dem::Mat3::Zero();
  D(0, 0) = a + b * c;
  D(1, 1) = a - b * c;
  D(0, 1) = D(1, 0) = b * s;
  return rate / D.norm() * D;
}

ProbeBase probe_base_from(const std::string& name) {
  if (name == "compression") return ProbeBase::compression;
  if (name == "shear") return ProbeBase::shear;
  if (name == "extension") return ProbeBase::extension;
  if (name == "oedometric") return ProbeBase::oedometric;
  if (name == "held_shear") return ProbeBase::held_shear;
  throw std::invalid_argument("unknown probe base \"" + name + "\"");
}

std::vector<PathPlan> probe_paths(const ProbeSpec& spec) {
  check(spec);
  std::vector<PathPlan> plans;
  for (ProbeBase base : spec.bases) {
    const std::vector<double> betas = has_stress_axes(base) ? spec.beta : std::vector<double>{0.0};
    for (double depth : spec.depths) {
      for (double rate : spec.rates) {
        PathPlan plan;
        plan.path.record_interval = spec.record_interval;
        plan.path.substepping = spec.substepping;
        plan.snapshot_interval = spec.snapshot_interval;
        plan.path.segments.push_back({base_gradient(base, spec.base_rate), depth / spec.base_rate,
                                      base == ProbeBase::held_shear ? spec.base_pressure : 0.0});
        const double duration = spec.probe_strain / rate;
        for (double psi : spec.psi) {
          for (double beta : betas) {
            const dem::Mat3 D = probe_direction(psi, base_axis(base) + beta, rate);
            plan.path.segments.push_back({D, duration});
            plan.path.segments.push_back({-D, duration});
          }
        }
        plans.push_back(std::move(plan));
      }
    }
  }
  return plans;
}

}  // namespace grainbank::sampler
