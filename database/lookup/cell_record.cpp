#include "database/lookup/cell_record.hpp"

#include "database/lookup/state_key.hpp"

namespace grainbank::lookup {

db::Record cell_record(const dem::DemCell& cell, const dem::Mat3& L, const dem::Mat3& stress,
                       const db::KeyScales& scales) {
  const dem::CellMeasures m = cell.measures();
  db::Record r;
  r.time = cell.time();
  r.F = cell.deformation_gradient();
  r.L = L;
  r.stress = db::to_stress6(stress);
  r.damage = m.damage;
  r.solid_fraction = m.solid_fraction;
  r.coordination = m.coordination;
  r.bonds = m.bonds;
  r.kinetic_energy = m.kinetic_energy;
  r.key = state_key(r.F, L, m.damage, scales);
  return r;
}

}  // namespace grainbank::lookup
