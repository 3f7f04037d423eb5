#include "database/surrogate/point_state.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace grainbank::surrogate {

void check(const FeatureConstants& c) {
  const auto require = [](double value, const char* name) {
    if (!(value > 0) || !std::isfinite(value))
      throw std::invalid_argument(std::string("surrogate constants: ") + name + ": expected a positive number, got " +
                                  std::to_string(value));
  };
  require(c.p_ref, "p_ref");
  require(c.p_floor, "p_floor");
  require(c.diameter, "diameter");
  require(c.density, "density");
}

double effective_pressure(const dem::Mat3& stress, const FeatureConstants& constants) {
  return std::max(-stress.trace() / 3, constants.p_floor);
}

}  // namespace grainbank::surrogate
