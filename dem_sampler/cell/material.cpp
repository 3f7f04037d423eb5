#include "dem_sampler/cell/material.hpp"

#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace grainbank::dem {
namespace {

void require(bool ok, const char* field, const char* expected, double got) {
  if (ok) return;
  std::ostringstream msg;
  msg << field << ": expected " << expected << ", got " << got;
  throw std::invalid_argument(msg.str());
}

bool finite(double v) { return std::isfinite(v); }

}  // namespace

void check(const Material& m) {
  require(finite(m.density) && m.density > 0, "density", "a positive number", m.density);
  const ContactLaw& c = m.contact;
  require(finite(c.k_n) && c.k_n > 0, "contact.k_n", "a positive number", c.k_n);
  require(finite(c.k_t) && c.k_t >= 0, "contact.k_t", "a number >= 0", c.k_t);
  require(finite(c.restitution) && c.restitution > 0 && c.restitution <= 1, "contact.restitution",
          "a number in (0, 1]", c.restitution);
  require(finite(c.friction) && c.friction >= 0, "contact.friction", "a number >= 0", c.friction);
  require(finite(c.contact_weight) && c.contact_weight >= 0 && c.contact_weight <= 1,
          "contact.contact_weight", "a number in [0, 1]", c.contact_weight);
  if (m.effects.bonds) {
    const BondLaw& b = m.bond;
    require(finite(b.tensile_strength) && b.tensile_strength > 0, "bond.tensile_strength",
            "a positive number", b.tensile_strength);
    require(finite(b.shear_strength) && b.shear_strength > 0, "bond.shear_strength",
            "a positive number", b.shear_strength);
    require(finite(b.exponent) && b.exponent >= 1, "bond.exponent", "a number >= 1", b.exponent);
    require(finite(b.bonding_distance) && b.bonding_distance >= 0, "bond.bonding_distance",
            "a number >= 0", b.bonding_distance);
    require(finite(b.softening) && b.softening >= 0, "bond.softening", "a number >= 0", b.softening);
    require(b.softening == 0 || b.exponent == 2, "bond.exponent",
            "2 when bond.softening > 0 (the softening law solves the quadratic yield surface)", b.exponent);
    require(c.contact_weight < 1, "contact.contact_weight",
            "a number < 1 when bonds are on (bonds carry 1 - w_c)", c.contact_weight);
  }
  if (m.effects.rolling) {
    require(finite(m.rolling.stiffness) && m.rolling.stiffness > 0, "rolling.stiffness",
            "a positive number", m.rolling.stiffness);
    require(finite(m.rolling.friction) && m.rolling.friction >= 0, "rolling.friction",
            "a number >= 0", m.rolling.friction);
  }
}

double damping_ratio_from_restitution(double e) {
  if (e >= 1) return 0;
  const double l = std::log(e);
  return -l / std::sqrt(std::numbers::pi * std::numbers::pi + l * l);
}

}  // namespace grainbank::dem
