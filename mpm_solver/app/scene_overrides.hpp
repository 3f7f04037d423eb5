// Command-line overrides of a scene (`--law`, `--library`), applied to the scene's JSON before it is
// parsed, so they need no knowledge of each law's parameters and keep working as DEM-backed laws
// are added. They act on the DEM-backed materials only (law `live`, `cache` or `hybrid`): analytic
// materials (elastic, Drucker–Prager) of the same scene are left as they are.
#pragma once
#include <filesystem>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

namespace grainbank::mpm::app {

struct SceneOverrides {
  std::optional<std::string> law;                // `--law NAME`: live, cache or hybrid
  std::optional<std::filesystem::path> library;  // `--library LIB`

  bool any() const { return law || library; }
};

// Returns `scene` with, in every DEM-backed material, "law" replaced by overrides.law (keys the new
// law does not take, such as a hybrid's "lookup" and "fallback" under --law live, are dropped) and
// "library" set to overrides.library (absolute; a "cell" entry is removed, since a library and a
// cell file are alternatives; the material's "template" id is kept). The material paths "cell" and
// "library" are made absolute against `scene_folder`, so the result can be read from anywhere.
// Throws common::InputError naming the flag and the expected value: an unknown law name, or a scene
// without any DEM-backed material to apply the flags to.
nlohmann::json apply_overrides(nlohmann::json scene, const std::filesystem::path& scene_folder,
                               const SceneOverrides& overrides);

}  // namespace grainbank::mpm::app
