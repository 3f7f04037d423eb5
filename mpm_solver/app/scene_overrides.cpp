#include "mpm_solver/app/scene_overrides.hpp"

#include <algorithm>
#include <cctype>
#include <span>
#include <string>
#include <vector>

#include "common/json_input.hpp"
#include "mpm_solver/laws/law_registry.hpp"

namespace grainbank::mpm::app {

namespace {

bool is_dem_backed(std::string_view law) {
  const std::optional<LawKind> kind = find_law_kind(law);
  return kind && kind->dem_backed;
}

bool dem_backed(const nlohmann::json& material) {
  const auto law = material.find("law");
  return law != material.end() && law->is_string() && is_dem_backed(law->get<std::string>());
}

// A relative path of the scene is relative to the scene's folder; the rewritten scene is read from
// elsewhere, so it gets the absolute path.
void make_absolute(nlohmann::json& material, const char* key, const std::filesystem::path& folder) {
  const auto it = material.find(key);
  if (it != material.end() && it->is_string())
    *it = std::filesystem::absolute(folder / it->get<std::string>()).lexically_normal().string();
}

// Keys of the material's old law that the new one does not take (a `lookup` block on a live
// material, a surrogate's `fallback.stress_tolerance` on a hybrid one) would be refused by the
// loader. A cache/hybrid material may name its cell next to its library (a check of the material); a
// live one takes one source, the library's template.
bool contains(std::span<const std::string_view> keys, std::string_view key) {
  return std::find(keys.begin(), keys.end(), key) != keys.end();
}

// The material's block `name` when it is an object (anything else is the loader's to refuse).
template <class Json>
Json* object_block(Json& material, std::string_view name) {
  const auto node = material.find(name);
  return node != material.end() && node->is_object() ? &*node : nullptr;
}

void erase_keys_not_in(nlohmann::json& object, std::span<const std::string_view> keys) {
  for (auto it = object.begin(); it != object.end();) it = contains(keys, it.key()) ? std::next(it) : object.erase(it);
}

void drop_keys_not_of(nlohmann::json& material, const std::string& law) {
  const LawKind kind = *find_law_kind(law);
  erase_keys_not_in(material, kind.keys);
  for (const KeyBlock& block : kind.blocks)
    if (nlohmann::json* node = object_block(material, block.name)) erase_keys_not_in(*node, block.keys);
  if (law == "live" && material.contains("library")) material.erase("cell");
}

// A patch naming a cell gives the material a cell of its own instead of the library's template.
void merge_material(nlohmann::json& material, const nlohmann::json& patch) {
  if (patch.contains("cell") && !patch["cell"].is_null()) {
    material.erase("library");
    material.erase("template");
  }
  material.merge_patch(patch);
  for (const char* key : {"cell", "library"})
    if (patch.contains(key)) make_absolute(material, key, std::filesystem::current_path());
}

// A merge patch may add a key the material's law does not take; the loader would refuse it only when
// the scene is run, so the rewritten scene is refused here, naming the key (a block's as
// "fallback.stress_tolerance").
void require_keys_in(const nlohmann::json& object, std::span<const std::string_view> keys, const std::string& prefix,
                     const std::string& law) {
  for (const auto& [key, value] : object.items())
    if (!contains(keys, key)) {
      std::string expected;
      for (std::string_view k : keys) expected.append(expected.empty() ? "" : ", ").append(k);
      throw common::InputError("--material: key \"" + prefix + key + "\" is not a key of law \"" + law +
                               "\" (expected one of " + expected + ")");
    }
}

void require_keys_of_its_law(const nlohmann::json& material) {
  const std::string law = material.value("law", "");
  const std::optional<LawKind> kind = find_law_kind(law);
  if (!kind) return;  // the loader names an unknown law
  require_keys_in(material, kind->keys, "", law);
  for (const KeyBlock& block : kind->blocks)
    if (const nlohmann::json* node = object_block(material, block.name))
      require_keys_in(*node, block.keys, std::string(block.name) + ".", law);
}

// The flags that act on the DEM-backed materials, as the user typed them ("--law/--material").
std::string material_flags(const SceneOverrides& o) {
  std::string flags;
  for (const auto& [given, name] : {std::pair{o.law.has_value(), "--law"}, {o.library.has_value(), "--library"},
                                    {o.material.has_value(), "--material"}})
    if (given) flags.append(flags.empty() ? "" : "/").append(name);
  return flags;
}

// An array index past the end would silently grow the array with nulls: along the pointer, every
// array must have the index (or "-", appending, at the end).
void check_indices(const nlohmann::json& scene, nlohmann::json::json_pointer pointer, const std::string& where) {
  std::vector<std::string> tokens;
  for (; !pointer.empty(); pointer.pop_back()) tokens.insert(tokens.begin(), pointer.back());
  const nlohmann::json* node = &scene;
  for (std::size_t i = 0; i < tokens.size() && node; ++i) {
    const std::string& token = tokens[i];
    if (!node->is_array()) {
      node = node->is_object() && node->contains(token) ? &(*node)[token] : nullptr;
      continue;
    }
    const bool index =
        !token.empty() && std::all_of(token.begin(), token.end(), [](unsigned char c) { return std::isdigit(c); });
    if (token == "-" && i + 1 == tokens.size()) return;
    if (!index || std::stoul(token) >= node->size())
      throw common::InputError(where + ": expected an index below " + std::to_string(node->size()) +
                               (i + 1 == tokens.size() ? " (or - to append)" : "") + ", got \"" + token + "\"");
    node = &(*node)[std::stoul(token)];
  }
}

void apply_setting(nlohmann::json& scene, const SceneSetting& setting) {
  const auto& [pointer, value] = setting;
  const std::string where = "--set " + pointer.to_string();
  if (pointer.empty()) throw common::InputError(where + ": expected a pointer to a key of the scene, got the root");
  check_indices(scene, pointer, where);
  try {
    scene[pointer] = value;
  } catch (const nlohmann::json::exception& e) {
    throw common::InputError(where + ": cannot be set in this scene (" + e.what() + ")");
  }
}

}  // namespace

nlohmann::json parse_material_patch(std::string_view text) {
  const nlohmann::json patch = nlohmann::json::parse(text, nullptr, false);
  if (!patch.is_object())
    throw common::InputError("--material: expected a JSON object of material keys, got \"" + std::string(text) + "\"");
  return patch;
}

SceneSetting parse_setting(std::string_view text) {
  const std::size_t equals = text.find('=');
  const std::string expected = "--set: expected /json/pointer=JSON value (e.g. /time/end=0.05), got \"" +
                               std::string(text) + "\"";
  if (equals == std::string_view::npos || text.empty() || text.front() != '/') throw common::InputError(expected);
  const nlohmann::json value = nlohmann::json::parse(text.substr(equals + 1), nullptr, false);
  if (value.is_discarded()) throw common::InputError(expected + ": the value is not JSON (a string needs quotes)");
  try {
    return {nlohmann::json::json_pointer(std::string(text.substr(0, equals))), value};
  } catch (const nlohmann::json::exception&) {
    throw common::InputError(expected + ": the pointer is not a JSON pointer");
  }
}

nlohmann::json apply_overrides(nlohmann::json scene, const std::filesystem::path& scene_folder,
                               const SceneOverrides& overrides) {
  if (overrides.law && !is_dem_backed(*overrides.law))
    throw common::InputError("--law: expected " + dem_backed_law_names() + ", got \"" + *overrides.law + "\"");
  if (overrides.library && overrides.library->empty())
    throw common::InputError("--library: expected a library directory, got an empty path");
  const auto materials = scene.find("materials");
  std::size_t rewritten = 0;
  if (materials != scene.end() && materials->is_array())
    for (nlohmann::json& m : *materials) {
      if (!m.is_object() || !dem_backed(m)) continue;
      ++rewritten;
      make_absolute(m, "cell", scene_folder);
      make_absolute(m, "library", scene_folder);
      if (overrides.law) {
        m["law"] = *overrides.law;
        drop_keys_not_of(m, *overrides.law);
      }
      if (overrides.library) {
        m.erase("cell");
        m["library"] = std::filesystem::absolute(*overrides.library).lexically_normal().string();
        if (!m.contains("template")) m["template"] = 1;  // a cell's material had none: the library's first
      }
      if (overrides.material) {
        merge_material(m, *overrides.material);
        require_keys_of_its_law(m);
      }
    }
  const std::string flags = material_flags(overrides);
  if (rewritten == 0 && !flags.empty())
    throw common::InputError(flags + ": expected a scene with a DEM-backed material (law " + dem_backed_law_names() +
                             "), found none");
  for (const SceneSetting& setting : overrides.settings) apply_setting(scene, setting);
  return scene;
}

}  // namespace grainbank::mpm::app
