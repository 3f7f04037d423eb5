#include "database/store/key_definition.hpp"

#include <stdexcept>

namespace grainbank::db {
namespace {
const std::array<std::string, kKeySize> kComponents = {"hencky_xx", "hencky_yy", "hencky_xy", "rate_xx",
                                                       "rate_yy",   "rate_xy",   "damage"};
}

nlohmann::json key_definition_json(const KeyScales& scales) {
  return {{"components", kComponents},
          {"frame", "material frame of the polar decomposition F = R U: Hencky strain 1/2 ln(F^T F) and R^T D R"},
          {"scales", {{"strain", scales.strain}, {"rate", scales.rate}, {"damage", scales.damage}}}};
}

KeyScales key_scales_from_json(const nlohmann::json& definition) {
  if (definition.at("components").get<std::array<std::string, kKeySize>>() != kComponents)
    throw std::invalid_argument("state key components " + definition.at("components").dump() +
                                " differ from this build's");
  const auto& s = definition.at("scales");
  return KeyScales{s.at("strain").get<double>(), s.at("rate").get<double>(), s.at("damage").get<double>()};
}

}  // namespace grainbank::db
