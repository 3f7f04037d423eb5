#include "dem_sampler/driver/cell_input.hpp"

#include <stdexcept>

#include "common/json_input.hpp"
#include "dem_sampler/driver/packing_csv.hpp"
#include "dem_sampler/driver/path_input.hpp"

namespace grainbank::app {
namespace {

using common::InputError;
using common::JsonNode;
using common::Range;

const Range kPositive = Range::positive();
const Range kNonNegative = Range::at_least(0);

dem::Effects read_effects(const JsonNode& root) {
  dem::Effects effects;
  const auto node = root.find("effects");
  if (!node) return effects;
  node->allow_only({"cohesion", "kinetic_stress", "rolling_resistance"});
  effects.bonds = node->boolean_or("cohesion", false);
  effects.kinetic_stress = node->boolean_or("kinetic_stress", false);
  effects.rolling = node->boolean_or("rolling_resistance", false);
  return effects;
}

// An optional block that must be present exactly when its effect is on: a block for an effect
// that is off would silently do nothing, which is worse than an error.
std::optional<JsonNode> effect_block(const JsonNode& material, std::string_view key, bool on,
                                     std::string_view effect, std::string_view expected) {
  const auto block = material.find(key);
  if (on && !block)
    material.fail_missing(key, std::string(expected) + " (/effects/" + std::string(effect) + " is true)");
  if (!on && block)
    block->fail("given but /effects/" + std::string(effect) + " is false; switch the effect on or remove this block");
  return block;
}

dem::Material read_material(const JsonNode& root) {
  dem::Material m;
  m.effects = read_effects(root);
  const JsonNode node = root.at("material", "an object");
  node.allow_only({"density", "k_n", "k_t", "restitution", "friction", "contact_weight", "bond", "rolling"});
  m.density = node.number("density", kPositive);
  m.contact.k_n = node.number("k_n", kPositive);
  m.contact.k_t = node.number("k_t", kNonNegative);
  m.contact.restitution = node.number("restitution", Range::between(0, 1, true, false));
  m.contact.friction = node.number("friction", kNonNegative);
  m.contact.contact_weight = node.number_or("contact_weight", 0.5, Range::between(0, 1, false, false));

  if (const auto bond = effect_block(node, "bond", m.effects.bonds, "cohesion",
                                     "an object {tensile_strength, shear_strength, exponent, bonding_distance, softening}")) {
    bond->allow_only({"tensile_strength", "shear_strength", "exponent", "bonding_distance", "softening"});
    m.bond.tensile_strength = bond->number("tensile_strength", kPositive);
    m.bond.shear_strength = bond->number("shear_strength", kPositive);
    m.bond.exponent = bond->number_or("exponent", 2, Range::at_least(1));
    m.bond.bonding_distance = bond->number("bonding_distance", kNonNegative);
    m.bond.softening = bond->number_or("softening", 0, kNonNegative);
  }
  if (const auto rolling = effect_block(node, "rolling", m.effects.rolling, "rolling_resistance",
                                        "an object {stiffness, friction}")) {
    rolling->allow_only({"stiffness", "friction"});
    m.rolling.stiffness = rolling->number("stiffness", kPositive);
    m.rolling.friction = rolling->number("friction", kNonNegative);
  }

  // The engine has the last word on consistency (e.g. w_c < 1 with bonds); its messages name
  // fields as "contact.k_n" or "bond.exponent", which map onto /material/k_n, /material/bond/exponent.
  try {
    dem::check(m);
  } catch (const std::invalid_argument& e) {
    std::string message = e.what();
    if (message.rfind("contact.", 0) == 0) message.erase(0, 8);
    const std::size_t colon = message.find(':');
    std::string field = message.substr(0, colon);
    for (char& c : field) c = c == '.' ? '/' : c;
    throw InputError(node.file() + ": /material/" + field + message.substr(colon));
  }
  return m;
}

dem::PreparationSpec read_preparation(const JsonNode& node) {
  node.allow_only({"spheres", "diameter", "pressure", "seed", "initial_solid_fraction", "compression_friction",
                   "pressure_tolerance", "unbalanced_force_tolerance", "inertial_number", "local_damping", "q_t",
                   "skin", "max_steps", "equilibrium_hold", "equilibrium_drift"});
  dem::PreparationSpec s;
  s.spheres = static_cast<std::size_t>(node.at("spheres", "an integer >= 2").integer(2, 10'000'000));
  const JsonNode diameter = node.at("diameter", "an object {min, max} [m]");
  diameter.allow_only({"min", "max"});
  s.min_diameter = diameter.number("min", kPositive);
  s.max_diameter = diameter.number("max", Range::at_least(s.min_diameter));
  s.pressure = node.number("pressure", kPositive);
  s.seed = static_cast<std::uint64_t>(node.at("seed", "an integer >= 0").integer(0));
  s.initial_solid_fraction =
      node.number_or("initial_solid_fraction", s.initial_solid_fraction, Range::between(0, 0.35, true, true));
  s.compression_friction = node.number_or("compression_friction", s.compression_friction, kNonNegative);
  s.pressure_tolerance = node.number_or("pressure_tolerance", s.pressure_tolerance, Range::between(0, 1, true, true));
  s.unbalanced_force_tolerance = node.number_or("unbalanced_force_tolerance", s.unbalanced_force_tolerance, kPositive);
  s.inertial_number = node.number_or("inertial_number", s.inertial_number, Range::between(0, 0.1, true, false));
  s.local_damping = node.number_or("local_damping", s.local_damping, Range::between(0, 1, false, true));
  s.q_t = node.number_or("q_t", s.q_t, Range::between(0, dem::kMaxTimeStepFactor, true, false));
  s.skin = node.number_or("skin", s.skin, Range::between(0, 1, true, false));
  s.max_steps = static_cast<long>(node.integer_or("max_steps", s.max_steps, 1));
  s.equilibrium_hold = node.number_or("equilibrium_hold", s.equilibrium_hold, kNonNegative);
  s.equilibrium_drift = node.number_or("equilibrium_drift", s.equilibrium_drift, kPositive);
  return s;
}

}  // namespace

CellInput load_cell_input(const std::filesystem::path& file) {
  const nlohmann::json document = common::load_json_file(file);
  const JsonNode root(document, file.string());
  root.allow_only({"material", "effects", "preparation", "packing", "skin"});
  CellInput input;
  input.material = read_material(root);
  const auto preparation = root.find("preparation");
  const auto packing = root.find("packing");
  if (preparation && packing) packing->fail("give either /preparation or /packing, not both");
  if (preparation) {
    if (const auto skin = root.find("skin")) skin->fail("only used with /packing; use /preparation/skin");
    input.preparation = read_preparation(*preparation);
    require_stable_q_t(*preparation, input.preparation->q_t, input.material.contact.restitution);
  } else if (packing) {
    input.packing = file.parent_path() / packing->string();
    input.packing_skin = root.number_or("skin", input.packing_skin, Range::between(0, 1, true, false));
  } else {
    root.fail_missing("preparation", "an object (or a \"packing\" file name instead)");
  }
  return input;
}

dem::DemCell build_cell(const CellInput& input, const dem::PreparationObserver& observer) {
  if (input.preparation) return dem::prepare_cell(input.material, *input.preparation, nullptr, observer);
  const Packing packing = read_packing_csv(*input.packing);
  double mean_diameter = 0;
  for (double r : packing.radii) mean_diameter += 2 * r;
  mean_diameter /= static_cast<double>(packing.radii.size());
  dem::DemCell cell = dem::DemCell::from_packing(packing.h, packing.positions, packing.radii, input.material,
                                                 input.packing_skin * mean_diameter);
  if (input.material.effects.bonds) cell.create_bonds(input.material.bond.bonding_distance);
  return cell;
}

}  // namespace grainbank::app
