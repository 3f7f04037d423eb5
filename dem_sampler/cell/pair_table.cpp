#include "dem_sampler/cell/pair_table.hpp"

namespace grainbank::dem {

PairTable PairTable::from_rows(const std::vector<Pair>& pairs, const std::vector<Bond>& bonds,
                               const std::vector<Vec3>& rolling) {
  PairTable t;
  const std::size_t n = pairs.size();
  t.i.resize(n);
  t.j.resize(n);
  t.image.resize(n);
  t.damping.resize(n);
  for (auto& c : t.ft) c.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Pair& p = pairs[k];
    t.i[k] = p.i;
    t.j[k] = p.j;
    t.image[k] = p.image;
    t.damping[k] = p.damping;
    for (int a = 0; a < 3; ++a) t.ft[a][k] = p.ft[a];
  }
  if (!bonds.empty()) {
    for (auto& c : t.bond_shear) c.resize(n);
    t.bond_rest_gap.resize(n);
    t.bond_integrity.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
      for (int a = 0; a < 3; ++a) t.bond_shear[a][k] = bonds[k].shear_displacement[a];
      t.bond_rest_gap[k] = bonds[k].rest_gap;
      t.bond_integrity[k] = bonds[k].integrity;
    }
  }
  if (!rolling.empty()) {
    for (auto& c : t.rolling) c.resize(n);
    for (std::size_t k = 0; k < n; ++k)
      for (int a = 0; a < 3; ++a) t.rolling[a][k] = rolling[k][a];
  }
  return t;
}

std::vector<Pair> PairTable::pair_rows() const {
  std::vector<Pair> rows(size());
  for (std::size_t k = 0; k < rows.size(); ++k) {
    Pair& p = rows[k];
    p.i = i[k];
    p.j = j[k];
    p.image = image[k];
    p.damping = damping[k];
    p.ft = Vec3(ft[0][k], ft[1][k], ft[2][k]);
  }
  return rows;
}

std::vector<Bond> PairTable::bond_rows() const {
  std::vector<Bond> rows(has_bonds() ? size() : 0);
  for (std::size_t k = 0; k < rows.size(); ++k)
    rows[k] = Bond{Vec3(bond_shear[0][k], bond_shear[1][k], bond_shear[2][k]), bond_rest_gap[k], bond_integrity[k]};
  return rows;
}

std::vector<Vec3> PairTable::rolling_rows() const {
  std::vector<Vec3> rows(has_rolling() ? size() : 0);
  for (std::size_t k = 0; k < rows.size(); ++k) rows[k] = Vec3(rolling[0][k], rolling[1][k], rolling[2][k]);
  return rows;
}

std::int64_t PairTable::intact_bonds() const {
  std::int64_t count = 0;
  for (double integrity : bond_integrity) count += integrity > 0 ? 1 : 0;
  return count;
}

std::size_t PairTable::memory_bytes() const {
  auto bytes = [](const auto& v) { return v.capacity() * sizeof(v[0]); };
  std::size_t total = bytes(i) + bytes(j) + bytes(image) + bytes(damping) + bytes(bond_rest_gap) + bytes(bond_integrity);
  for (int a = 0; a < 3; ++a) total += bytes(ft[a]) + bytes(bond_shear[a]) + bytes(rolling[a]);
  return total;
}

}  // namespace grainbank::dem
