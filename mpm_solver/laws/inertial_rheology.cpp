#include "mpm_solver/laws/inertial_rheology.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace grainbank::mpm {

double InertialRheology::friction(double mu_s, double inertial_number) const {
  return mu_s + (mu_2 - mu_s) * inertial_number / (inertial_number_0 + inertial_number);
}

double InertialRheology::plastic_shear_rate(double excess, double mu_s, double p, double shear_modulus,
                                            double dt) const {
  // With ξ = G Δt, b = d sqrt(ρ_s / p) (so I = b γ̇) and Δμ = μ_2 − μ_s, the return
  //   excess − ξ γ̇ = Δμ p b γ̇ / (I_0 + b γ̇)
  // is ξ b γ̇² + (ξ I_0 + Δμ p b − excess b) γ̇ − excess I_0 = 0: a product of roots < 0, so one
  // positive root, taken in the form that does not cancel.
  const double xi = shear_modulus * dt, b = grain_diameter * std::sqrt(grain_density / p);
  const double a = xi * b, half_b = 0.5 * (xi * inertial_number_0 + (mu_2 - mu_s) * p * b - excess * b);
  const double c = excess * inertial_number_0;
  const double root = std::sqrt(half_b * half_b + a * c);
  return half_b > 0 ? c / (half_b + root) : (root - half_b) / a;
}

void check(const InertialRheology& r, double mu_s) {
  if (!(r.mu_2 >= mu_s) || !std::isfinite(r.mu_2))
    throw std::invalid_argument("mu_2: expected a number >= the static friction sin(friction_angle) = " +
                                std::to_string(mu_s) + ", got " + std::to_string(r.mu_2));
  if (!(r.inertial_number_0 > 0) || !std::isfinite(r.inertial_number_0))
    throw std::invalid_argument("inertial_number_0: expected a positive number, got " +
                                std::to_string(r.inertial_number_0));
  if (!(r.grain_diameter > 0) || !std::isfinite(r.grain_diameter))
    throw std::invalid_argument("grain_diameter: expected a positive number [m], got " + std::to_string(r.grain_diameter));
  if (!(r.grain_density > 0) || !std::isfinite(r.grain_density))
    throw std::invalid_argument("grain_density: expected a positive number [kg/m^3], got " +
                                std::to_string(r.grain_density));
}

}  // namespace grainbank::mpm
