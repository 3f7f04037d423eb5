#include "library_record.hpp"

#include "lookup/state_key.hpp"

namespace grainbank::sampler {

db::Record to_library_record(const app::PathRecord& record, const dem::Mat3& L, const db::KeyScales& scales) {
  db::Record r;
  r.time = record.time;
  r.F = record.F;
  r.L = L;
  r.stress = db::to_stress6(record.stress);
  r.damage = record.measures.damage;
  r.solid_fraction = record.measures.solid_fraction;
  r.coordination = record.measures.coordination;
  r.bonds = record.measures.bonds;
  r.kinetic_energy = record.measures.kinetic_energy;
  r.key = lookup::state_key(record.F, L, record.measures.damage, scales);
  return r;
}

}  // namespace grainbank::sampler
