#include "dem_sampler/cell/effective_medium.hpp"

#include <numbers>

namespace grainbank::dem {

ElasticModuli voigt_moduli(double solid_fraction, double coordination, double mean_radius, double k_n, double k_t) {
  const double scale = solid_fraction * coordination / (std::numbers::pi * mean_radius);
  return {scale * k_n / 6, scale * (2 * k_n + 3 * k_t) / 20};
}

}  // namespace grainbank::dem
