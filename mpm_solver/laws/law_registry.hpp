// The constitutive laws a scene can name, each registered by the file that defines it (the way
// LAMMPS styles register): a law file ends with
//   const LawRegistration registration{{"name", keys, dem_backed, &read, runs_on_ranks, blocks}};
// and nothing else in the tree lists laws. The scene reader, `mpm_solver laws` and the scene
// overrides ask this registry.
//
// Promise: every registered name is unique (a second registration of a name throws at start-up);
// a law's reader accepts exactly its published keys (its JSON object is checked with allow_only), and
// in its published blocks exactly their keys.
#pragma once
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "common/json_input.hpp"
#include "mpm_solver/core/constitutive_law.hpp"

namespace grainbank::mpm {

// The DEM effects a scene declares (absent: whatever its cells have). A DEM-backed material whose
// cell or library was built with other effects is refused: its responses answer another physics.
struct DemEffects {
  std::optional<bool> cohesion, kinetic_stress, rolling_resistance;
};

// What a law's reader needs of the scene besides its own JSON object.
struct LawContext {
  std::filesystem::path folder;  // the scene file's folder: relative file names are resolved here
  DemEffects effects;
  int rank = 0, ranks = 1;  // this MPI rank and the number of ranks the run is spread over (core/ranks.hpp)
};

using LawReader = std::unique_ptr<ConstitutiveLaw> (*)(const common::JsonNode& material, const LawContext& scene);

// A block of a material object whose keys depend on the law (a "fallback" is the hybrid's live
// fallback or the surrogate's warm start), and every key it may have.
struct KeyBlock {
  std::string_view name;
  std::span<const std::string_view> keys;
};

struct LawKind {
  std::string_view name;                  // the value of the material's "law" key
  std::span<const std::string_view> keys;  // every key its material object may have, "name" and "law" included
  bool dem_backed = false;                // its points are answered by DEM cells (live or from a library)
  LawReader read = nullptr;               // builds the law; errors name the file and JSON pointer
  // The law runs on several MPI ranks (its instances are replicable() or have a point_sharing()):
  // a scene on several ranks refuses any other before building it (building may take a library's
  // writer lock, which only one rank would get).
  bool runs_on_ranks = false;
  std::span<const KeyBlock> blocks = {};  // its blocks whose keys are its own; its reader accepts exactly these
};

// All registered kinds, sorted by name.
std::vector<LawKind> law_kinds();
// The kind registered under `name`, if any.
std::optional<LawKind> find_law_kind(std::string_view name);
// "\"cache\", \"drucker_prager\", ... or \"live\"": for messages; of all kinds or of the DEM-backed ones.
std::string law_names();
std::string dem_backed_law_names();

// Reads one material object: dispatches on its "law" key.
std::unique_ptr<ConstitutiveLaw> read_law(const common::JsonNode& material, const LawContext& scene);

// Constructing one (at namespace scope, in the law's own file) registers the kind.
struct LawRegistration {
  explicit LawRegistration(LawKind kind);
};

}  // namespace grainbank::mpm
