// Command-line overrides of a scene (`--law`, `--library`, `--material`, `--set`), applied to the
// scene's JSON before it is parsed, so they need no knowledge of each law's parameters and keep
// working as laws are added. `--law`, `--library` and `--material` act on the DEM-backed materials
// only (law `live`, `cache` or `hybrid`): analytic materials (elastic, Drucker–Prager) of the same
// scene are left as they are. This is the one generator of scene variants: the workflows call
// `mpm_solver scene` instead of rewriting scenes themselves.
#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace grainbank::mpm::app {

// `--set /json/pointer=VALUE`: the scene key at the pointer set to the JSON value.
using SceneSetting = std::pair<nlohmann::json::json_pointer, nlohmann::json>;

struct SceneOverrides {
  std::optional<std::string> law;                // `--law NAME`: a DEM-backed law (live, cache, hybrid)
  std::optional<std::filesystem::path> library;  // `--library LIB`
  std::optional<nlohmann::json> material;        // `--material JSON`: a merge patch (RFC 7396)
  std::vector<SceneSetting> settings;            // `--set POINTER=VALUE`, in order

  bool any() const { return law || library || material || !settings.empty(); }
};

// Parse the text of `--material` (a JSON object) and of one `--set` (POINTER=JSON, e.g.
// `/time/end=0.05` or `/grid/cells=[8,4]`). Throw common::InputError naming the flag and the
// expected value.
nlohmann::json parse_material_patch(std::string_view text);
SceneSetting parse_setting(std::string_view text);

// Returns `scene` with, in every DEM-backed material:
// - "law" replaced by overrides.law (keys the new law does not take, such as a hybrid's "lookup" and
//   "fallback" under --law live, are dropped);
// - "library" set to overrides.library (absolute; a "cell" entry is removed, since a library and a
//   cell file are alternatives; the material's "template" id is kept, 1 when it has none);
// - overrides.material merged in last (a "cell" there replaces the library and template; null
//   removes a key; its relative "cell" and "library" are relative to the working directory).
// The material paths "cell" and "library" are made absolute against `scene_folder`, so the result can
// be read from anywhere. Then each setting is applied to the whole scene, in order.
// Throws common::InputError naming the flag and the expected value: an unknown law name, a --material
// key that the material's law does not take, or a scene without any DEM-backed material to apply
// --law, --library or --material to.
nlohmann::json apply_overrides(nlohmann::json scene, const std::filesystem::path& scene_folder,
                               const SceneOverrides& overrides);

}  // namespace grainbank::mpm::app
