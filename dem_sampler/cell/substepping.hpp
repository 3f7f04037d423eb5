// How a periodic cell is driven through one macroscopic (MPM) increment: the time-step rule of seed
// Eq. 3 and the stress regression of seed Fig. 3.
#pragma once
#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>

#include "dem_sampler/cell/material.hpp"
#include "dem_sampler/cell/types.hpp"

namespace grainbank::dem {

// Largest accepted Q_t without dashpots. Velocity Verlet on dense bonded packings (125 spheres, Z =
// 6.8-8.4, k_t/k_n from 0.1 to 1, no damping) stayed stable to Q_t = 0.25 with the step of
// dem_time_step and went unstable from about 0.26-0.3; 0.2 keeps a margin.
inline constexpr double kMaxTimeStepFactor = 0.2;

// Largest accepted Q_t for contact dashpots of restitution e_n. The force loop sees a dashpot at the
// half-step velocity, so on a mode of frequency ω and damping ratio ζ velocity Verlet is stable only
// for ω δt < 2 (√(1 + ζ²) − ζ), not 2: a dashpot lowers the stable step. The bound keeps
// kMaxTimeStepFactor's margin over it, with ζ the contact's own (damping_ratio_from_restitution).
// Measured on the demo's bonded cell (250 spheres, e_n = 0.3, ζ = 0.358, factor 0.704), held at rest
// for 5 ms: it broke 9.4 % of its bonds at Q_t = 0.2 and 3.0 % at 0.19, none at 0.18 and below (its
// pressure moved by 0.8 % at 0.18, not at all at 0.175); the bound is 0.141.
inline double max_time_step_factor(double restitution) {
  const double zeta = damping_ratio_from_restitution(restitution);
  return kMaxTimeStepFactor * (std::sqrt(1 + zeta * zeta) - zeta);
}

// "expected a number in (0, BOUND] (why), got Q_T" when q_t is not an accepted factor for contact
// dashpots of restitution e_n; nothing when it is.
inline std::optional<std::string> time_step_factor_error(double q_t, double restitution) {
  const double bound = max_time_step_factor(restitution);
  if (q_t > 0 && q_t <= bound) return std::nullopt;
  std::ostringstream msg;
  msg << "expected a number in (0, " << bound << "] (velocity Verlet is unstable beyond it on dense packings";
  if (bound < kMaxTimeStepFactor)
    msg << "; dashpots of restitution " << restitution << " lower the undamped bound " << kMaxTimeStepFactor
        << " by the factor " << bound / kMaxTimeStepFactor;
  msg << "), got " << q_t;
  return msg.str();
}

// Throws std::invalid_argument("FIELD: " + time_step_factor_error) when q_t is not accepted.
inline void require_stable_time_step_factor(double q_t, double restitution, std::string_view field) {
  if (const auto error = time_step_factor_error(q_t, restitution))
    throw std::invalid_argument(std::string(field) + ": " + *error);
}

struct Substepping {
  double q_t = 0.1;      // Q_t in (0, max_time_step_factor(e_n)]: δt = Q_t π sqrt(m_min / k_max), see dem_time_step
  int q_n = 1;           // Q_n: at least this many DEM steps per increment
  double q_sigma = 0.2;  // Q_σ: regress the stress over this last fraction of the increment
};

// Seed Eq. 3 (the seed prints sqrt(k_n/m); dimensionally the step is a fraction of the contact
// half-period), over every stiff mode of the smallest sphere (mass m, radius R, I = 2/5 m R²), not
// only the normal one: δt = Q_t π sqrt(m / k_max) with k_max the largest of
//  - k_n, the normal spring;
//  - 3.5 k_t: a tangential spring at the contact point moves the centre and the spin at once,
//    u = x + R θ, so m ü = -k_t (1 + m R²/I) u;
//  - 2.5 k_r / R²: the rolling spring turns the sphere alone, I θ̈ = -k_r θ, i.e. δt ≤ Q_t π sqrt(I / k_r).
// k_r = 0 when rolling resistance is off.
inline double dem_time_step(double q_t, double min_mass, double min_radius, double k_n, double k_t, double k_r) {
  const double inertia_ratio = 2.5;  // m R² / I of a solid sphere
  const double k_max =
      std::max({k_n, (1 + inertia_ratio) * k_t, inertia_ratio * k_r / (min_radius * min_radius)});
  return q_t * std::numbers::pi * std::sqrt(min_mass / k_max);
}

// n = max(ceil(Δt/δt), Q_n) steps of exactly Δt/n: the cell receives exactly the macroscopic
// increment, never up to one δt more.
inline long substep_count(double increment_duration, double dem_step, int q_n) {
  if (!(increment_duration > 0) || !(dem_step > 0))
    throw std::invalid_argument("substep_count: durations must be positive");
  const double n = std::ceil(increment_duration / dem_step * (1 - 1e-12));
  return std::max(static_cast<long>(n), static_cast<long>(std::max(q_n, 1)));
}

// Least-squares line through (t_k, σ_k) for each stress component, evaluated at a given time
// (seed Fig. 3). Per call state only: every driven cell owns its own.
class StressRegression {
 public:
  void add(double t, const Mat3& stress) {
    ++count_;
    sum_t_ += t;
    sum_tt_ += t * t;
    sum_s_ += stress;
    sum_ts_ += t * stress;
    last_ = stress;
  }
  int count() const { return count_; }
  Mat3 at(double t) const {
    if (count_ < 2) return last_;
    const double n = count_, denom = n * sum_tt_ - sum_t_ * sum_t_;
    if (denom <= 0) return last_;
    const Mat3 slope = (n * sum_ts_ - sum_t_ * sum_s_) / denom;
    const Mat3 intercept = (sum_s_ - slope * sum_t_) / n;
    return intercept + slope * t;
  }

 private:
  int count_ = 0;
  double sum_t_ = 0, sum_tt_ = 0;
  Mat3 sum_s_ = Mat3::Zero(), sum_ts_ = Mat3::Zero(), last_ = Mat3::Zero();
};

}  // namespace grainbank::dem
