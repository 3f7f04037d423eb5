// The two laws a scene names that LibraryLaw implements, "cache" and "hybrid": their keys, their
// reader and their registration. A material names the library (and template) its points are
// answered from; with "cell", the library must have been built for that cell's material.
#include <optional>

#include "dem_sampler/driver/cell_input.hpp"
#include "mpm_solver/dem_laws/dem_material_input.hpp"
#include "mpm_solver/dem_laws/library_law.hpp"
#include "mpm_solver/laws/law_registry.hpp"
#include "database/store/error.hpp"

namespace grainbank::mpm {

namespace {

using common::JsonNode;
using common::Range;

constexpr std::string_view kCacheKeys[] = {"name", "law", "library", "template", "cell", "lookup", "substepping", "q_h", "retiling"};
constexpr std::string_view kHybridKeys[] = {"name",   "law",         "library", "template", "cell",
                                            "lookup", "substepping", "q_h", "retiling", "fallback", "enrich",
                                            "snapshot_interval", "snapshot_budget"};
constexpr std::string_view kLookupKeys[] = {"k", "tolerance", "scales"};
constexpr std::string_view kHybridFallbackKeys[] = {"start", "max_drive_strain", "return_after"};
constexpr KeyBlock kCacheBlocks[] = {{"lookup", kLookupKeys}};
constexpr KeyBlock kHybridBlocks[] = {{"lookup", kLookupKeys}, {"fallback", kHybridFallbackKeys}};

// "lookup": {"k", "tolerance", "scales": {"strain", "rate", "damage"}}; the scales replace the
// library's key scales for this run: what "a different state" means here.
std::optional<db::KeyScales> read_lookup(const JsonNode& material, lookup::LookupOptions& options) {
  const auto node = material.find("lookup");
  if (!node) return std::nullopt;
  node->allow_only(kLookupKeys);
  options.k = static_cast<std::size_t>(node->integer_or("k", static_cast<std::int64_t>(options.k), 1, 1000));
  options.tolerance = node->number_or("tolerance", options.tolerance, Range::at_least(0));
  const auto scales = node->find("scales");
  if (!scales) return std::nullopt;
  scales->allow_only({"strain", "rate", "damage"});
  return db::KeyScales{scales->number("strain", Range::positive()), scales->number("rate", Range::positive()),
                       scales->number("damage", Range::positive())};
}

// "fallback": {"start": "warm_start" | "replay", "max_drive_strain", "return_after"}, "enrich",
// "snapshot_interval", "snapshot_budget": how a missed point turns live and what its cell gives back.
void read_fallback(const JsonNode& material, LibraryLawSettings& s) {
  s.fallback = Fallback::warm_start;
  if (const auto fb = material.find("fallback")) {
    fb->allow_only(kHybridFallbackKeys);
    if (const auto start = fb->find("start")) {
      const std::string kind = start->string();
      if (kind == "replay") s.fallback = Fallback::replay;
      else if (kind != "warm_start") start->fail_expected("\"warm_start\" or \"replay\"");
    }
    s.max_drive_strain = fb->number_or("max_drive_strain", s.max_drive_strain, Range::positive());
    s.return_after = static_cast<int>(fb->integer_or("return_after", s.return_after, 0, 1000000000));
  }
  s.enrich = material.boolean_or("enrich", true);
  s.snapshot_interval = static_cast<int>(material.integer_or("snapshot_interval", s.snapshot_interval, 0, 1000000000));
  s.snapshot_budget = static_cast<long>(material.integer_or("snapshot_budget", s.snapshot_budget, 0, 1000000000000));
}

std::unique_ptr<ConstitutiveLaw> read(const JsonNode& material, const LawContext& scene, bool hybrid) {
  LibraryLawSettings s;
  s.live = read_live_settings(material);
  const std::optional<db::KeyScales> scales = read_lookup(material, s.lookup);
  if (hybrid) read_fallback(material, s);
  s.rank = scene.rank, s.ranks = scene.ranks;
  const JsonNode lib = material.at("library", "a library directory (string)");
  const std::int64_t id = material.at("template", "a template id (integer)").integer(1);
  std::optional<dem::Material> expected;
  if (material.has("cell")) expected = app::load_cell_input(scene.folder / material.at("cell", "").string()).material;
  std::unique_ptr<LibraryLink> link;
  try {
    link = std::make_unique<LibraryLink>(scene.folder / lib.string(), id, expected ? &*expected : nullptr, scales);
  } catch (const db::StoreError& e) {
    lib.fail(e.what());
  }
  require_compatible(material, link->template_cell().material(), scene.effects, "the library " + lib.string(), s.live);
  return common::at_node(material, [&] { return std::make_unique<LibraryLaw>(std::move(link), s); });
}

std::unique_ptr<ConstitutiveLaw> read_cache(const JsonNode& material, const LawContext& scene) {
  return read(material, scene, false);
}
std::unique_ptr<ConstitutiveLaw> read_hybrid(const JsonNode& material, const LawContext& scene) {
  return read(material, scene, true);
}

const LawRegistration cache{{"cache", kCacheKeys, true, &read_cache, true, kCacheBlocks}};
const LawRegistration hybrid{{"hybrid", kHybridKeys, true, &read_hybrid, true, kHybridBlocks}};

}  // namespace

}  // namespace grainbank::mpm
