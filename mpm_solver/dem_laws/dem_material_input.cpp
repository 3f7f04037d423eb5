#include "mpm_solver/dem_laws/dem_material_input.hpp"

#include "dem_sampler/driver/cell_input.hpp"
#include "dem_sampler/driver/path_input.hpp"
#include "database/store/library.hpp"

namespace grainbank::mpm {

using common::JsonNode;
using common::Range;

LiveDemSettings read_live_settings(const JsonNode& material) {
  LiveDemSettings s;
  if (const auto sub = material.find("substepping")) {
    sub->allow_only({"q_t", "q_n", "q_sigma"});
    s.substepping.q_t = sub->number_or("q_t", s.substepping.q_t, Range::between(0, dem::kMaxTimeStepFactor, true, false));
    s.substepping.q_n = static_cast<int>(sub->integer_or("q_n", s.substepping.q_n, 1, 1000000));
    s.substepping.q_sigma = sub->number_or("q_sigma", s.substepping.q_sigma, Range::between(0, 1, true, false));
  }
  s.q_h = material.number_or("q_h", s.q_h, Range::positive());
  if (const auto retiling = material.find("retiling")) {
    retiling->allow_only({"max_spheres", "beyond_cap"});
    s.max_spheres = static_cast<std::size_t>(retiling->integer_or("max_spheres", 0, 0, 100000000));
    if (const auto beyond = retiling->find("beyond_cap")) {
      const std::string name = beyond->string();
      if (name != "stop" && name != "regenerate") beyond->fail("expected \"stop\" or \"regenerate\"");
      s.regenerate_beyond_cap = name == "regenerate";
      if (s.regenerate_beyond_cap && s.max_spheres == 0)
        beyond->fail("\"regenerate\" needs a \"max_spheres\" cap above the cell's sphere count");
    }
  }
  return s;
}

dem::DemCell read_cell_template(const JsonNode& material, const std::filesystem::path& folder) {
  if (material.has("cell") == material.has("library"))
    material.fail("a live material needs exactly one of \"cell\" (a cell.json) and \"library\" with \"template\"");
  if (material.has("cell")) return app::build_cell(app::load_cell_input(folder / material.at("cell", "").string()));
  const JsonNode lib = material.at("library", "");
  const std::int64_t id = material.at("template", "a template id (integer)").integer(1);
  try {
    db::Library library = db::Library::open(folder / lib.string());
    return library.restore(library.template_cell(id));
  } catch (const std::exception& e) {
    lib.fail(e.what());
  }
}

void require_compatible(const JsonNode& material, const dem::Material& built, const DemEffects& scene,
                        const std::string& source, const LiveDemSettings& live) {
  const auto check = [&](const char* name, const std::optional<bool>& wanted, bool on) {
    if (wanted && *wanted != on)
      material.fail(source + " was built with " + name + (on ? " on" : " off") + " but the scene's effects." + name +
                    " is " + (*wanted ? "on" : "off") + "; the run is refused (use a library or cell with the same effects)");
  };
  check("cohesion", scene.cohesion, built.effects.bonds);
  check("kinetic_stress", scene.kinetic_stress, built.effects.kinetic_stress);
  check("rolling_resistance", scene.rolling_resistance, built.effects.rolling);
  const auto substepping = material.find("substepping");
  app::require_stable_q_t(substepping ? *substepping : material, live.substepping.q_t, built.contact.restitution);
}

}  // namespace grainbank::mpm
