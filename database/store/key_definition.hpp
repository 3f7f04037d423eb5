// The definition of the state key (DESIGN.md, "Nearest-state lookup"), stored in the catalogue meta
// so that a library stays readable when the defaults change: which components, and the scale that
// makes a unit distance in each of them mean "a different state".
#pragma once
#include <array>
#include <string>

#include <nlohmann/json.hpp>

#include "database/store/record.hpp"

namespace grainbank::db {

struct KeyScales {
  double strain = 1e-2;  // Hencky strain per unit key distance
  double rate = 1.0;     // strain rate per unit key distance [1/s]; from an inertial-number scale
                         // I_ref sqrt(p0/ρ)/d chosen by whoever builds the library
  double damage = 5e-2;  // damage per unit key distance
  bool operator==(const KeyScales&) const = default;
};

// {"components": [...7 names...], "frame": ..., "scales": {"strain": .., "rate": .., "damage": ..}}
nlohmann::json key_definition_json(const KeyScales& scales);
// Throws std::invalid_argument when the stored definition has other components than this build's.
KeyScales key_scales_from_json(const nlohmann::json& definition);

}  // namespace grainbank::db
