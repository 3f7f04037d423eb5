#include "dem_sampler/sampler/path_generator.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "dem_sampler/sampler/halton.hpp"

namespace grainbank::sampler {
namespace {

constexpr double kRootHalf = std::numbers::sqrt2 / 2;

// D of unit Frobenius norm from two uniform numbers (an area-uniform point of the sphere).
dem::Mat3 direction(double u1, double u2, double volumetric_weight) {
  const double a = 1 - 2 * u1, r = std::sqrt(std::max(0.0, 1 - a * a));
  double vol = volumetric_weight * a, dev = r * std::cos(2 * std::numbers::pi * u2),
         shear = r * std::sin(2 * std::numbers::pi * u2);
  const double norm = std::sqrt(vol * vol + dev * dev + shear * shear);
  if (norm == 0) vol = 0, dev = 1, shear = 0;  // only with zero volumetric weight at a pole
  else vol /= norm, dev /= norm, shear /= norm;
  dem::Mat3 D = dem::Mat3::Zero();
  D(0, 0) = kRootHalf * (vol + dev);
  D(1, 1) = kRootHalf * (vol - dev);
  D(0, 1) = D(1, 0) = kRootHalf * shear;
  return D;
}

dem::Mat3 spin(double magnitude) {
  dem::Mat3 W = dem::Mat3::Zero();
  W(0, 1) = kRootHalf * magnitude;
  W(1, 0) = -kRootHalf * magnitude;
  return W;
}

dem::Mat3 rotate_principal_axes(const dem::Mat3& L, double angle) {
  dem::Mat3 Q = dem::Mat3::Identity();
  Q(0, 0) = Q(1, 1) = std::cos(angle);
  Q(1, 0) = std::sin(angle);
  Q(0, 1) = -Q(1, 0);
  const dem::Mat3 D = 0.5 * (L + L.transpose()), W = 0.5 * (L - L.transpose());
  return Q * D * Q.transpose() + W;
}

void check(const GeneratorSpec& s) {
  const auto fail = [](const std::string& what) { throw std::invalid_argument("path generator: " + what); };
  if (s.count < 1) fail("count must be >= 1");
  if (!(s.min_rate > 0) || !(s.max_rate >= s.min_rate)) fail("rates must satisfy 0 < min <= max");
  if (!(s.strain > 0)) fail("strain must be positive");
  if (s.segments < 1 || s.segments > kMaxSegments) fail("segments must be in [1, 10]");
  if (s.segments > 1 && s.changes.empty()) fail("changes must not be empty");
  if (!(s.volumetric >= 0 && s.volumetric <= 1)) fail("volumetric must be in [0, 1]");
  if (!(s.spin >= 0 && s.spin <= 1)) fail("spin must be in [0, 1]");
  if (!(s.record_interval > 0)) fail("record_interval must be positive");
}

}  // namespace

DirectionChange direction_change_from(const std::string& name) {
  if (name == "reversal") return DirectionChange::reversal;
  if (name == "rotation") return DirectionChange::rotation;
  if (name == "fresh") return DirectionChange::fresh;
  throw std::invalid_argument("unknown direction change \"" + name + "\"");
}

std::vector<PathPlan> generate_paths(const GeneratorSpec& spec) {
  check(spec);
  std::vector<PathPlan> plans;
  const double log_span = std::log(spec.max_rate / spec.min_rate);
  for (long i = 0; i < spec.count; ++i) {
    const std::uint64_t index = spec.start + static_cast<std::uint64_t>(i) + 1;
    const double rate = spec.min_rate * std::exp(log_span * halton(index, 2));
    dem::Mat3 L = rate * direction(halton(index, 0), halton(index, 1), spec.volumetric) +
                  spin(spec.spin * rate * (2 * halton(index, 3) - 1));
    PathPlan plan;
    plan.path.record_interval = spec.record_interval;
    plan.path.substepping = spec.substepping;
    plan.snapshot_interval = spec.snapshot_interval;
    const double duration = spec.strain / spec.segments / rate;
    for (int k = 0; k < spec.segments; ++k) {
      if (k > 0) {
        const std::size_t dim = 4 + 2 * static_cast<std::size_t>(k - 1);
        switch (spec.changes[static_cast<std::size_t>(k - 1) % spec.changes.size()]) {
          case DirectionChange::reversal: L = -L; break;
          case DirectionChange::rotation:
            L = rotate_principal_axes(L, std::numbers::pi / 2 * (0.1 + 0.8 * halton(index, dim)));
            break;
          case DirectionChange::fresh:
            L = rate * direction(halton(index, dim), halton(index, dim + 1), spec.volumetric) +
                0.5 * (L - L.transpose());
            break;
        }
      }
      plan.path.segments.push_back({L, duration});
    }
    plans.push_back(std::move(plan));
  }
  return plans;
}

}  // namespace grainbank::sampler
