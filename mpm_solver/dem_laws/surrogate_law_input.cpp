// The "surrogate" law's scene JSON: its keys, their checks, and the library it is read from.
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "dem_sampler/driver/cell_input.hpp"
#include "mpm_solver/dem_laws/dem_material_input.hpp"
#include "mpm_solver/dem_laws/library_link.hpp"
#include "mpm_solver/dem_laws/surrogate_law.hpp"
#include "mpm_solver/laws/law_registry.hpp"
#include "database/store/error.hpp"
#include "database/surrogate/reindex.hpp"

namespace grainbank::mpm {

namespace {

using common::JsonNode;
using common::Range;

// {"law": "surrogate", "library": LIB, "template": id, "tolerance": Pa} with the optional "cell"
// (the library must have its material), "error_budget" [Pa], "k", "sample_span", "fit_seed" (which
// probes the length-scale fit uses, length_scales.hpp), "pressure_floor" (p_floor / p_ref, reindex.hpp),
// "fallback":
// {"return_after", "warm_start": "state" | "replay", "stress_tolerance" [Pa, default: tolerance],
// "max_servo_steps", "servo_inertial_number", "catch_up_steps", "catch_up_legs",
// "catch_up_strain_per_step", "first_cell":
// "template" | "snapshot", "unconverged": "keep" | "replay"}, and the "substepping", "q_h" and
// "retiling" of every DEM-backed law.
constexpr std::string_view kKeys[] = {"name", "law", "library",     "template", "cell",    "tolerance",
                                      "error_budget", "k",  "sample_span", "fit_seed", "pressure_floor",
                                      "substepping", "q_h", "retiling", "fallback"};
constexpr std::string_view kFallbackKeys[] = {"return_after",   "warm_start",    "stress_tolerance",
                                              "max_servo_steps", "servo_inertial_number", "catch_up_steps",
                                              "catch_up_legs",  "catch_up_strain_per_step", "first_cell",
                                              "unconverged"};
constexpr KeyBlock kBlocks[] = {{"fallback", kFallbackKeys}};

std::unique_ptr<ConstitutiveLaw> read(const JsonNode& material, const LawContext& scene) {
  SurrogateLawSettings s;
  s.live = read_live_settings(material);
  s.tolerance = material.number("tolerance", Range::at_least(0));
  s.error_budget = material.number_or("error_budget", s.error_budget, Range::positive());
  s.surrogate.k = static_cast<std::size_t>(material.integer_or("k", static_cast<std::int64_t>(s.surrogate.k), 1, 1000));
  s.sample_span = static_cast<std::size_t>(
      material.integer_or("sample_span", static_cast<std::int64_t>(s.sample_span), 1, 1000));
  s.fit.seed = static_cast<std::uint64_t>(material.integer_or("fit_seed", 0, 0, 1000000000));
  const double pressure_floor =
      material.number_or("pressure_floor", surrogate::kPressureFloor, common::Range::between(0, 1, true, false));
  if (const auto fallback = material.find("fallback")) {
    fallback->allow_only(kFallbackKeys);
    s.return_after = static_cast<int>(fallback->integer_or("return_after", s.return_after, 0, 1000000000));
    if (const auto mode = fallback->find("warm_start")) {
      const std::string name = mode->string();
      if (name != "state" && name != "replay") mode->fail("expected \"state\" or \"replay\"");
      s.warm_start = name == "state" ? SurrogateLawSettings::WarmStart::state : SurrogateLawSettings::WarmStart::replay;
    }
    StateWarmStartSettings& w = s.state_warm_start;
    if (fallback->has("stress_tolerance")) w.stress_tolerance = fallback->number("stress_tolerance", Range::positive());
    w.max_servo_steps = fallback->integer_or("max_servo_steps", w.max_servo_steps, 1, 1000000000);
    w.servo_inertial_number = fallback->number_or("servo_inertial_number", w.servo_inertial_number, Range::positive());
    w.catch_up_steps = fallback->integer_or("catch_up_steps", w.catch_up_steps, 1, 1000000000);
    w.catch_up_legs = fallback->integer_or("catch_up_legs", w.catch_up_legs, 1, 1000000000);
    w.catch_up_strain_per_step =
        fallback->number_or("catch_up_strain_per_step", w.catch_up_strain_per_step, Range::at_least(0));
    if (const auto first = fallback->find("first_cell")) {
      const std::string name = first->string();
      if (name != "template" && name != "snapshot") first->fail("expected \"template\" or \"snapshot\"");
      w.first_cell = name == "template" ? StateWarmStartSettings::FirstCell::template_caught_up
                                        : StateWarmStartSettings::FirstCell::nearest_snapshot;
    }
    if (const auto unconverged = fallback->find("unconverged")) {
      const std::string name = unconverged->string();
      if (name != "keep" && name != "replay") unconverged->fail("expected \"keep\" or \"replay\"");
      w.replay_unconverged = name == "replay";
    }
  }
  const JsonNode lib = material.at("library", "a library directory (string)");
  const std::int64_t id = material.at("template", "a template id (integer)").integer(1);
  std::optional<dem::Material> expected;
  if (material.has("cell")) expected = app::load_cell_input(scene.folder / material.at("cell", "").string()).material;
  std::unique_ptr<LibraryLink> link;
  surrogate::Dataset dataset;
  std::vector<StateSnapshot> snapshots;
  try {
    link = std::make_unique<LibraryLink>(scene.folder / lib.string(), id, expected ? &*expected : nullptr);
    dataset = link->locked([&](db::Library& library) { return surrogate::reindex(library, s.sample_span, pressure_floor); });
    if (s.warm_start == SurrogateLawSettings::WarmStart::state &&
        s.state_warm_start.first_cell == StateWarmStartSettings::FirstCell::nearest_snapshot)
      snapshots = link->state_snapshots();
  } catch (const db::StoreError& e) {
    lib.fail(e.what());
  }
  require_compatible(material, link->template_cell().material(), scene.effects, "the library " + lib.string(), s.live);
  return common::at_node(material,
                         [&] { return std::make_unique<SurrogateLaw>(link->template_cell(), std::move(dataset), s, std::move(snapshots)); });
}

const LawRegistration registration{{"surrogate", kKeys, true, &read, false, kBlocks}};

}  // namespace

}  // namespace grainbank::mpm
