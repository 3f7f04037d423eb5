#include "database/surrogate/state_features.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

namespace grainbank::surrogate {

namespace {

constexpr double kPi = std::numbers::pi;

// (−π/2, π/2]: principal axes are directions, so angles between them are defined modulo π.
double wrap_half_turn(double angle) {
  while (angle > kPi / 2) angle -= kPi;
  while (angle <= -kPi / 2) angle += kPi;
  return angle;
}

// Lode angle of a deviator s (tension-positive), θ ∈ [0, π/3]; 0 for s = 0.
double lode_angle(const dem::Mat3& s) {
  const double j2 = 0.5 * (s.array() * s.array()).sum();
  if (!(j2 > 1e-300)) return 0;
  const double c = 1.5 * std::sqrt(3.0) * s.determinant() / std::pow(j2, 1.5);
  return std::acos(std::clamp(c, -1.0, 1.0)) / 3;
}

}  // namespace

double pressure_feature(double pressure, const FeatureConstants& constants) {
  if (pressure >= constants.p_floor) return std::log(pressure / constants.p_ref);
  // Below the floor the normalization no longer tells pressures apart (p_eff = p_floor), so the key
  // must: a bonded cell near its tensile strength answers unlike a cell barely compressed. The mirror
  // of the logarithm keeps the feature monotone and C¹ through the floor and logarithmic in tension.
  return std::log(constants.p_floor / constants.p_ref) - std::log(2 - pressure / constants.p_floor);
}

double effective_pressure_of_feature(double feature, const FeatureConstants& constants) {
  return std::max(constants.p_ref * std::exp(feature), constants.p_floor);
}

std::optional<double> in_plane_principal_angle(const dem::Mat3& t) {
  const double a = t(0, 0) - t(1, 1), b = t(0, 1) + t(1, 0);
  // Below this relative size the in-plane deviator is round-off of an in-plane isotropic tensor.
  if (!(std::hypot(a, b) > 1e-12 * (std::abs(t(0, 0)) + std::abs(t(1, 1)) + std::abs(b)))) return std::nullopt;
  return wrap_half_turn(0.5 * std::atan2(b, a));
}

double answer_frame_angle(const dem::Mat3& stress, const dem::Mat3& L) {
  if (const auto angle = in_plane_principal_angle(stress)) return *angle;
  return in_plane_principal_angle(0.5 * (L + L.transpose())).value_or(0.0);
}

StateFeatures state_features(const PointState& state, const dem::Mat3& L, const FeatureConstants& constants) {
  const dem::Mat3 sigma = 0.5 * (state.stress + state.stress.transpose());
  const double p = effective_pressure(sigma, constants);
  const dem::Mat3 s = sigma - (sigma.trace() / 3) * dem::Mat3::Identity();
  const double q = std::sqrt(1.5 * (s.array() * s.array()).sum());

  const dem::Mat3 D = 0.5 * (L + L.transpose());
  const dem::Mat3 dev_D = D - (D.trace() / 3) * dem::Mat3::Identity();
  const double rate = D.norm();

  StateFeatures f;
  f.log_pressure = pressure_feature(-sigma.trace() / 3, constants);
  f.eta = q / p;
  f.lode = lode_angle(s);
  f.solid_fraction = state.solid_fraction;
  f.coordination = state.coordination;
  f.damage = state.damage;
  if (rate > 0) {
    f.psi = std::atan2(D.trace(), dev_D.norm());
    // β is measured from the answer frame: 0 when D has no in-plane axes, or σ has none (the frame
    // is then D's own).
    const auto axis_D = in_plane_principal_angle(D);
    if (axis_D) f.beta = wrap_half_turn(*axis_D - answer_frame_angle(sigma, L));
  }
  f.inertial = rate * constants.diameter * std::sqrt(constants.density / p);
  return f;
}

FeatureVector feature_vector(const StateFeatures& f) {
  constexpr double kInertialFloor = 1e-8;  // ln I of a point at rest: far below any sampled rate
  return {f.log_pressure,
          f.eta * std::cos(3 * f.lode),
          f.eta * std::sin(3 * f.lode),
          f.solid_fraction,
          f.coordination,
          f.damage,
          std::sin(f.psi),
          std::cos(f.psi) * std::cos(2 * f.beta),
          std::cos(f.psi) * std::sin(2 * f.beta),
          std::log(std::max(f.inertial, kInertialFloor))};
}

}  // namespace grainbank::surrogate
