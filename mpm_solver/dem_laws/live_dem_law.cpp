#include "mpm_solver/dem_laws/live_dem_law.hpp"

#include <string>

#include "dem_sampler/cell/cell_state_bytes.hpp"

#include "mpm_solver/dem_laws/dem_material_input.hpp"
#include "mpm_solver/laws/law_registry.hpp"

namespace grainbank::mpm {

LiveDemLaw::LiveDemLaw(const dem::DemCell& cell_template, LiveDemSettings settings) : model_(cell_template, settings) {}

std::size_t LiveDemLaw::add_point(PointStress& initial_stress) {
  cells_.push_back(model_.new_cell());  // a deep copy: the point owns its cell
  counters_.emplace_back();
  modulus_.push_back(0);
  damage_.push_back(0);
  measure(cells_.size() - 1);
  initial_stress = plane_stress_of(cells_.back().measures().stress);
  return cells_.size() - 1;
}

void LiveDemLaw::update(std::size_t slot, const KinematicIncrement& increment, const Mat2&, PointStress& stress) {
  stress = plane_stress_of(model_.advance(cells_[slot], increment, counters_[slot]));
  measure(slot);
}

namespace {
constexpr const char* kCounterTable = "live_counters";  // per point: retilings, regenerations, unconverged
constexpr std::size_t kCounterColumns = 3;
constexpr const char* kHoldTable = "live_dispersed_holds";  // per point (absent in older files: 0)
}  // namespace

void LiveDemLaw::save_state(LawStateWriter& out) const {
  std::vector<double> counters, holds;
  for (std::size_t slot = 0; slot < cells_.size(); ++slot) {
    out.write_cell("cell_" + std::to_string(slot), cells_[slot]);
    const CouplingCounters& c = counters_[slot];
    counters.insert(counters.end(), {double(c.retilings), double(c.regenerations), double(c.regenerations_unconverged)});
    holds.push_back(double(c.dispersed_holds));
  }
  out.write_table(kCounterTable, counters, kCounterColumns);
  out.write_table(kHoldTable, holds, 1);
}

void LiveDemLaw::restore_state(LawStateReader& in) {
  const std::vector<double> counters =
      in.has_table(kCounterTable) ? in.read_table(kCounterTable, kCounterColumns) : std::vector<double>{};
  const std::vector<double> holds = in.has_table(kHoldTable) ? in.read_table(kHoldTable, 1) : std::vector<double>{};
  for (std::size_t slot = 0; slot < cells_.size(); ++slot) {
    cells_[slot] = model_.cell_from(in.read_cell("cell_" + std::to_string(slot)));
    CouplingCounters& c = counters_[slot];
    if (counters.size() == kCounterColumns * cells_.size()) {
      c.retilings = static_cast<std::uint64_t>(counters[kCounterColumns * slot]);
      c.regenerations = static_cast<std::uint64_t>(counters[kCounterColumns * slot + 1]);
      c.regenerations_unconverged = static_cast<std::uint64_t>(counters[kCounterColumns * slot + 2]);
    } else {
      // A restart of a build that did not store the counters had no regeneration: every point
      // started from the template, so its cell's size tells how often it was re-tiled.
      c = CouplingCounters{};
      LiveCellModel::count_retilings(model_.template_size(), cells_[slot], c);
    }
    if (holds.size() == cells_.size()) c.dispersed_holds = static_cast<std::uint64_t>(holds[slot]);
    measure(slot);
  }
}

void LiveDemLaw::write_summary(std::size_t slot, common::ByteWriter& out) const {
  out.put(modulus_[slot]), out.put(damage_[slot]), out.put(counters_[slot]);
}

void LiveDemLaw::read_summary(std::size_t slot, common::ByteReader& in) {
  modulus_[slot] = in.get<double>();
  damage_[slot] = in.get<double>();
  counters_[slot] = in.get<CouplingCounters>();
}

void LiveDemLaw::write_point_state(std::size_t slot, common::ByteWriter& out) const {
  dem::write_cell_state(cells_[slot].state(), out);
  out.put(counters_[slot]);
}

void LiveDemLaw::read_point_state(std::size_t slot, common::ByteReader& in) {
  cells_[slot] = model_.cell_from(dem::read_cell_state(in));
  counters_[slot] = in.get<CouplingCounters>();
  measure(slot);
}

void LiveDemLaw::measure(std::size_t slot) {
  const dem::CellMeasures m = cells_[slot].measures();
  modulus_[slot] = model_.modulus(m);
  damage_[slot] = m.damage;
}

double LiveDemLaw::volume_ratio(std::size_t slot, double) const {
  return model_.volume_ratio(cells_[slot]);
}

double LiveDemLaw::time_step_limit(std::size_t slot, const Mat2&, const Mat2& L) const {
  return model_.time_step_limit(cells_[slot], L);
}

namespace {

// {"law": "live", "cell": "cell.json"} or {"law": "live", "library": LIB, "template": id}, with the
// optional "substepping", "q_h" and "retiling" of every DEM-backed law.
constexpr std::string_view kKeys[] = {"name", "law", "cell", "library", "template", "substepping", "q_h", "retiling"};

std::unique_ptr<ConstitutiveLaw> read(const common::JsonNode& material, const LawContext& scene) {
  const LiveDemSettings settings = read_live_settings(material);
  const dem::DemCell cell = read_cell_template(material, scene.folder);
  require_compatible(material, cell.material(), scene.effects, material.has("cell") ? "the cell" : "the library",
                     settings);
  return common::at_node(material, [&] { return std::make_unique<LiveDemLaw>(cell, settings); });
}

const LawRegistration registration{{"live", kKeys, true, &read, true}};

}  // namespace

}  // namespace grainbank::mpm
