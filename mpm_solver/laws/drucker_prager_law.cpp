#include "mpm_solver/laws/drucker_prager_law.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "common/json_input.hpp"
#include "mpm_solver/laws/law_registry.hpp"

namespace grainbank::mpm {

DruckerPragerLaw::DruckerPragerLaw(double density, DruckerPragerParameters parameters)
    : density_(density), parameters_(parameters) {
  if (!(density > 0) || !std::isfinite(density))
    throw std::invalid_argument("density: expected a positive number, got " + std::to_string(density));
  check(parameters_.elasticity);
  const double phi = parameters_.friction_angle;
  if (!(phi >= 0 && phi < std::numbers::pi / 2))
    throw std::invalid_argument("friction_angle: expected an angle in [0, 90) degrees");
  if (!(parameters_.cohesion >= 0) || !std::isfinite(parameters_.cohesion))
    throw std::invalid_argument("cohesion: expected a number >= 0, got " + std::to_string(parameters_.cohesion));
  const double psi = parameters_.dilatancy_angle;
  if (!(psi >= 0 && psi <= phi))
    throw std::invalid_argument("dilatancy_angle: expected an angle in [0, friction_angle = " +
                                std::to_string(phi * 180 / std::numbers::pi) + "] degrees");
  if (psi > 0 && parameters_.rheology)
    throw std::invalid_argument("inertial_rheology: only with dilatancy_angle 0");
  // The plane-strain Mohr–Coulomb match of the header.
  eta_bar_ = std::sin(psi) / std::sqrt(1 + std::sin(psi) * std::sin(psi) / 3);
  const double root = std::sqrt(1 - eta_bar_ * eta_bar_ / 3);
  eta_ = std::sin(phi) / (root + eta_bar_ * std::sin(phi) / 3);
  xi_ = std::cos(phi) * (1 - eta_ * eta_bar_ / 3) / root;
  const double apex = eta_ > 0 ? xi_ * parameters_.cohesion / eta_ : std::numeric_limits<double>::infinity();
  if (!(parameters_.tensile_strength >= 0 && parameters_.tensile_strength <= apex))
    throw std::invalid_argument("tensile_strength: expected a number in [0, " + std::to_string(apex) +
                                "] (the apex of the yield cone), got " + std::to_string(parameters_.tensile_strength));
  if (parameters_.rheology) check(*parameters_.rheology, eta_);
  if (parameters_.separation && parameters_.cohesion > 0)
    throw std::invalid_argument("separation: expected a cohesionless material (cohesion 0), got cohesion " +
                                std::to_string(parameters_.cohesion));
}

std::size_t DruckerPragerLaw::add_point(PointStress& initial_stress) {
  initial_stress = PointStress{};
  packing_.emplace_back();
  return packing_.size() - 1;
}

double DruckerPragerLaw::p_wave_modulus(std::size_t slot) const {
  const double modulus = parameters_.elasticity.p_wave_modulus();
  const Packing& packing = packing_[slot];
  return packing.separated_at > 0 ? modulus * packing.separated_at / packing.volume_ratio : modulus;
}

PointStress DruckerPragerLaw::return_map(const PointStress& trial, double dt) const {
  double p = pressure_of(trial);
  const Mat2 s_plane = trial.in_plane + p * Mat2::Identity();  // deviator, in-plane block
  const double s_zz = trial.zz + p;
  p = std::max(p, -parameters_.tensile_strength);  // tension cut-off
  const double s_xy = 0.5 * (s_plane(0, 1) + s_plane(1, 0));
  const double j2 = 0.5 * (s_plane(0, 0) * s_plane(0, 0) + s_plane(1, 1) * s_plane(1, 1) + s_zz * s_zz) + s_xy * s_xy;
  const double static_limit = std::max(eta_ * p + xi_ * parameters_.cohesion, 0.0);
  double scale = 1.0;
  if (j2 > static_limit * static_limit) {
    const double tau = std::sqrt(j2);
    double limit = static_limit;
    const double g = parameters_.elasticity.shear_modulus();
    if (parameters_.rheology && p > 0) {
      // Flowing: the strength grows with the rate of the flow it relaxes (seed §2.2's I).
      limit = tau - g * dt * parameters_.rheology->plastic_shear_rate(tau - static_limit, eta_, p, g, dt);
    } else if (eta_bar_ > 0 && static_limit > 0) {
      // Dilating as it flows: the pressure rises with the plastic volume change while the deviator
      // falls, both by the same Δλ, until the stress is on the cone.
      const double bulk = parameters_.elasticity.bulk_modulus();
      const double delta_lambda = (tau - static_limit) / (g + bulk * eta_ * eta_bar_);
      p += bulk * eta_bar_ * delta_lambda;
      limit = tau - g * delta_lambda;
    }
    scale = limit / tau;
  }
  PointStress out;
  out.in_plane = scale * s_plane - p * Mat2::Identity();
  out.zz = scale * s_zz - p;
  return out;
}

void DruckerPragerLaw::update(std::size_t slot, const KinematicIncrement& increment, const Mat2& /*F*/,
                              PointStress& stress) {
  if (!parameters_.separation) {
    stress = return_map(elastic_predictor(parameters_.elasticity, stress, increment), increment.dt);
    return;
  }
  Packing& packing = packing_[slot];
  // Where the step starts on the elastic line: its volume and pressure (zero when packed back). The
  // volume follows the motion, J e^{tr L dt}, the same measure as the elastic line's pressure, and
  // not det F, which round-off takes once a lone front point's F has been sheared without bound.
  double start_volume = packing.volume_ratio;
  const double volume = start_volume * std::exp(increment.L.trace() * increment.dt);
  packing.volume_ratio = volume;
  KinematicIncrement loading = increment;
  if (packing.separated_at > 0) {
    // Apart: no stress. Back exactly at J_s is still apart: its pressure is zero there, and a point
    // that came apart from zero stress has J_s equal to its volume to the bit.
    if (volume >= packing.separated_at) {
      stress = PointStress{};
      return;
    }
    // Packed back within the step: only the motion after contact loads it, from zero stress (never
    // more than the step's motion: the elastic line and the volume agree only to round-off).
    if (start_volume > volume) {
      const double after_contact =
          std::min(1.0, std::log(packing.separated_at / volume) / std::log(start_volume / volume));
      loading = KinematicIncrement::of_velocity_gradient(increment.L, after_contact * increment.dt);
    }
    start_volume = packing.separated_at;
    packing.separated_at = 0;
    stress = PointStress{};
  }
  const double start_pressure = pressure_of(stress);
  const PointStress trial = elastic_predictor(parameters_.elasticity, stress, loading);
  if (pressure_of(trial) < 0) {
    // Came apart within the step, where its pressure reached zero on the elastic line: at J e^{p/K}
    // from the step's start.
    stress = PointStress{};
    packing.separated_at = start_volume * std::exp(start_pressure / parameters_.elasticity.bulk_modulus());
    return;
  }
  stress = return_map(trial, increment.dt);
}

void DruckerPragerLaw::save_state(LawStateWriter& out) const {
  if (!parameters_.separation) return;
  std::vector<double> rows;
  rows.reserve(2 * packing_.size());
  for (const Packing& p : packing_) rows.insert(rows.end(), {p.separated_at, p.volume_ratio});
  out.write_table("packing", rows, 2);
}

void DruckerPragerLaw::restore_state(LawStateReader& in) {
  if (!parameters_.separation) return;
  const std::vector<double> rows = in.read_table("packing", 2);
  if (rows.size() != 2 * packing_.size())
    throw std::runtime_error("drucker_prager restart: " + std::to_string(rows.size() / 2) + " points' packing for " +
                             std::to_string(packing_.size()) + " points");
  for (std::size_t i = 0; i < packing_.size(); ++i) packing_[i] = {rows[2 * i], rows[2 * i + 1]};
}

namespace {

// {"law": "drucker_prager", "density": ρ, "young": E, "poisson": ν, "friction_angle": φ [degrees],
//  "cohesion": c [Pa] (0), "tensile_strength": [Pa] (0), "dilatancy_angle": ψ [degrees] (0),
//  "separation": pulled apart, carries nothing until packed back (false; cohesion 0 only),
//  "inertial_rheology": {"mu_2": μ_2, "inertial_number_0": I_0, "grain_diameter": d [m],
//                        "grain_density": ρ_s [kg/m³]} (none: rate-independent)}
constexpr std::string_view kKeys[] = {"name",     "law",      "density",          "young",           "poisson",
                                      "friction_angle", "cohesion", "tensile_strength", "inertial_rheology",
                                      "dilatancy_angle", "separation"};

InertialRheology read_rheology(const common::JsonNode& node) {
  using common::Range;
  node.allow_only({"mu_2", "inertial_number_0", "grain_diameter", "grain_density"});
  return {node.number("mu_2", Range::at_least(0)), node.number("inertial_number_0", Range::positive()),
          node.number("grain_diameter", Range::positive()), node.number("grain_density", Range::positive())};
}

std::unique_ptr<ConstitutiveLaw> read(const common::JsonNode& material, const LawContext&) {
  using common::Range;
  DruckerPragerParameters p;
  p.elasticity = read_elasticity(material);
  p.friction_angle = material.number("friction_angle", Range::between(0, 90, false, true)) * std::numbers::pi / 180;
  p.cohesion = material.number_or("cohesion", 0, Range::at_least(0));
  p.tensile_strength = material.number_or("tensile_strength", 0, Range::at_least(0));
  if (const auto rheology = material.find("inertial_rheology")) p.rheology = read_rheology(*rheology);
  p.dilatancy_angle = material.number_or("dilatancy_angle", 0, Range::between(0, 90, false, true)) * std::numbers::pi / 180;
  p.separation = material.boolean_or("separation", false);
  return common::at_node(material, [&] {
    return std::make_unique<DruckerPragerLaw>(material.number("density", Range::positive()), p);
  });
}

const LawRegistration registration{{"drucker_prager", kKeys, false, &read, true}};

}  // namespace

}  // namespace grainbank::mpm
