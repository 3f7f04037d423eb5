#include "live_dem_law.hpp"

namespace grainbank::mpm {

LiveDemLaw::LiveDemLaw(const dem::DemCell& cell_template, LiveDemSettings settings) : model_(cell_template, settings) {}

std::size_t LiveDemLaw::add_point(PointStress& initial_stress) {
  cells_.push_back(model_.new_cell());  // a deep copy: the point owns its cell
  modulus_.push_back(0);
  damage_.push_back(0);
  measure(cells_.size() - 1);
  initial_stress = plane_stress_of(cells_.back().measures().stress);
  return cells_.size() - 1;
}

void LiveDemLaw::update(std::size_t slot, const KinematicIncrement& increment, const Mat2&, PointStress& stress) {
  stress = plane_stress_of(model_.advance(cells_[slot], increment));
  measure(slot);
}

void LiveDemLaw::restore_cell(std::size_t slot, dem::CellState state) {
  cells_[slot] = model_.cell_from(std::move(state));
  measure(slot);
}

void LiveDemLaw::measure(std::size_t slot) {
  const dem::CellMeasures m = cells_[slot].measures();
  modulus_[slot] = model_.modulus(m);
  damage_[slot] = m.damage;
}

double LiveDemLaw::volume_ratio(std::size_t slot, const Mat2&) const {
  return cells_[slot].volume() / model_.template_volume();
}

double LiveDemLaw::time_step_limit(std::size_t slot, const Mat2&, const Mat2& L) const {
  return model_.time_step_limit(cells_[slot].cell_matrix(), L);
}

}  // namespace grainbank::mpm
