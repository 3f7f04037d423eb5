#include "app/scene_overrides.hpp"

#include <algorithm>
#include <string_view>

#include "common/json_input.hpp"
#include "laws/law_registry.hpp"

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
// material) would be refused by the loader. A cache/hybrid material may name its cell next to its
// library (a check of the material); a live one takes one source, the library's template.
void drop_keys_not_of(nlohmann::json& material, const std::string& law) {
  const std::span<const std::string_view> keys = find_law_kind(law)->keys;
  for (auto it = material.begin(); it != material.end();)
    it = std::find(keys.begin(), keys.end(), it.key()) == keys.end() ? material.erase(it) : std::next(it);
  if (law == "live" && material.contains("library")) material.erase("cell");
}

}  // namespace

nlohmann::json apply_overrides(nlohmann::json scene, const std::filesystem::path& scene_folder,
                               const SceneOverrides& overrides) {
  const std::string flags = overrides.law && overrides.library ? "--law/--library" : overrides.law ? "--law" : "--library";
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
      }
    }
  if (rewritten == 0)
    throw common::InputError(flags + ": expected a scene with a DEM-backed material (law " + dem_backed_law_names() +
                             "), found none");
  return scene;
}

}  // namespace grainbank::mpm::app
