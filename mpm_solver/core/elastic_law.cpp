#include "elastic_law.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace grainbank::mpm {

void check(const Elasticity& e) {
  if (!(e.young > 0) || !std::isfinite(e.young))
    throw std::invalid_argument("young: expected a positive number, got " + std::to_string(e.young));
  if (!(e.poisson > -1 && e.poisson < 0.5))
    throw std::invalid_argument("poisson: expected a number in (-1, 0.5), got " + std::to_string(e.poisson));
}

PointStress elastic_predictor(const Elasticity& e, const PointStress& stress, const Mat2& F_inc) {
  const Mat2 de = strain_increment(F_inc), dw = spin_increment(F_inc);
  const double lambda = e.lame_lambda(), two_g = 2 * e.shear_modulus();
  const double volumetric = lambda * de.trace();
  PointStress trial;
  trial.in_plane = stress.in_plane + dw * stress.in_plane - stress.in_plane * dw + two_g * de +
                   volumetric * Mat2::Identity();
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

void ElasticLaw::update(std::size_t, const Mat2& F_inc, double, PointStress& stress) {
  stress = elastic_predictor(elasticity_, stress, F_inc);
}

}  // namespace grainbank::mpm
