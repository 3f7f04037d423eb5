// Builds test inputs as "a good document with one change", so each error case states only its change.
#pragma once
#include <nlohmann/json.hpp>
#include <string>

namespace grainbank::testing {

inline std::string with(nlohmann::json document, const std::string& pointer, const nlohmann::json& value) {
  document[nlohmann::json::json_pointer(pointer)] = value;
  return document.dump(2);
}

inline std::string without(nlohmann::json document, const std::string& pointer) {
  const nlohmann::json::json_pointer p(pointer);
  document[p.parent_pointer()].erase(p.back());
  return document.dump(2);
}

}  // namespace grainbank::testing
