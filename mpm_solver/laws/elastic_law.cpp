#include "mpm_solver/laws/elastic_law.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>

#include "common/json_input.hpp"
#include "mpm_solver/laws/law_registry.hpp"

namespace grainbank::mpm {

void check(const Elasticity& e) {
  if (!(e.young > 0) || !std::isfinite(e.young))
    throw std::invalid_argument("young: expected a positive number, got " + std::to_string(e.young));
  if (!(e.poisson > -1 && e.poisson < 0.5))
    throw std::invalid_argument("poisson: expected a number in (-1, 0.5), got " + std::to_string(e.poisson));
}

Elasticity read_elasticity(const common::JsonNode& material) {
  using common::Range;
  return {material.number("young", Range::positive()), material.number("poisson", Range::between(-1, 0.5, true, true))};
}

PointStress elastic_predictor(const Elasticity& e, const PointStress& stress, const KinematicIncrement& increment) {
  const Mat2 de = increment.strain();
  const double lambda = e.lame_lambda(), two_g = 2 * e.shear_modulus();
  const double volumetric = lambda * de.trace();
  // The Jaumann term σ̇ = W σ - σ W integrated exactly over the increment (W constant): the stress
  // turns by R = exp(W dt), keeping its invariants, however many steps a skipped increment spans.
  const Mat2 R = Eigen::Rotation2Dd(increment.spin()(1, 0)).toRotationMatrix();
  PointStress trial;
  trial.in_plane = R * stress.in_plane * R.transpose() + two_g * de + volumetric * Mat2::Identity();
  trial.zz = stress.zz + volumetric;  // plane strain: dε_zz = 0
  return trial;
}

ElasticLaw::ElasticLaw(double density, Elasticity elasticity) : density_(density), elasticity_(elasticity) {
  if (!(density > 0) || !std::isfinite(density))
    throw std::invalid_argument("density: expected a positive number, got " + std::to_string(density));
  check(elasticity_);
}

std::size_t ElasticLaw::add_point(PointStress& initial_stress) {
  initial_stress = PointStress{};
  return points_++;
}

void ElasticLaw::update(std::size_t, const KinematicIncrement& increment, const Mat2&, PointStress& stress) {
  stress = elastic_predictor(elasticity_, stress, increment);
}

namespace {

// {"law": "elastic", "density": ρ [kg/m³], "young": E [Pa], "poisson": ν}
constexpr std::string_view kKeys[] = {"name", "law", "density", "young", "poisson"};

std::unique_ptr<ConstitutiveLaw> read(const common::JsonNode& material, const LawContext&) {
  return common::at_node(material, [&] {
    return std::make_unique<ElasticLaw>(material.number("density", common::Range::positive()), read_elasticity(material));
  });
}

const LawRegistration registration{{"elastic", kKeys, false, &read, true}};

}  // namespace

}  // namespace grainbank::mpm
