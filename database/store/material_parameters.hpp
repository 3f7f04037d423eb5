// The physical identity of a library: every parameter of a dem::Material (interaction laws and
// effects), as JSON for the catalogue, as a parameter hash for quick comparison, and as a list of
// named differences for error messages. Parameters of switched-off effects count too: the hash says
// "same inputs", not "same physics under some reading of which inputs matter".
// Parameters added later (bond.softening) are left out of the JSON and the hash at the value every
// older library has, and read as that value when absent, so older libraries keep their identity.
#pragma once
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "dem_sampler/cell/material.hpp"

namespace grainbank::db {

// {"density": ..., "contact": {"k_n": ...}, ..., "effects": {"bonds": false, ...}}; doubles are
// written with enough digits to read back exactly.
nlohmann::json material_to_json(const dem::Material& material);
// Inverse of material_to_json; throws std::invalid_argument naming the first missing parameter.
dem::Material material_from_json(const nlohmann::json& json);

// 16 hex digits (FNV-1a 64) over the exact bits of every parameter, in a fixed order.
std::string parameter_hash(const dem::Material& material);

// One line per differing parameter: "contact.friction: library 0.5, given 0.4". Empty when equal.
std::vector<std::string> material_differences(const dem::Material& library, const dem::Material& given);

// FNV-1a 64 of arbitrary text, as 16 hex digits (spec hashes, template tokens).
std::string text_hash(const std::string& text);

}  // namespace grainbank::db
