// The snow-like cohesive material of the seed's column collapse (mean grain diameter ≈ 0.37 mm,
// ice density, soft bonded contacts; parameters of the reference implementation's RVE), prepared at
// 1 kPa. Used by examples, benchmarks and tests that need a realistic small cohesive cell.
#pragma once
#include <cstdint>

#include "dem_sampler/cell/material.hpp"
#include "dem_sampler/cell/preparation.hpp"

namespace grainbank::dem {

inline Material snow_material() {
  Material m;
  m.density = 920;
  m.contact = {2000, 600, 0.3, 0.2, 0.5};
  m.effects.bonds = true;
  m.bond = {8e-4, 9.6e-4, 2, 0.05};
  return m;
}

inline PreparationSpec snow_preparation(std::size_t spheres, std::uint64_t seed) {
  PreparationSpec spec;
  spec.spheres = spheres;
  spec.min_diameter = 3.4e-4;
  spec.max_diameter = 4.0e-4;
  spec.pressure = 1000;
  spec.inertial_number = 0.01;
  spec.seed = seed;
  return spec;
}

}  // namespace grainbank::dem
