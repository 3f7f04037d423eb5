// The Verlet pairs of a cell and their interaction history as columns (structure of arrays): the
// layout the vectorized force loop reads, one contiguous array per quantity, so that a SIMD register
// of consecutive pairs loads with one instruction. CellState holds the same content as rows (Pair,
// Bond, rolling moment); the two convert into each other at list rebuilds and snapshots only.
#pragma once
#include <cstdint>
#include <vector>

#include "dem_sampler/cell/cell_state.hpp"

namespace grainbank::dem {

struct PairTable {
  std::vector<std::uint32_t> i, j, image;    // spheres i < j and the shift code of j's image
  std::vector<double> damping;               // normal dashpot c_n [N·s/m]
  std::vector<double> ft[3];                 // tangential contact spring force on j
  // Bonds (empty unless the bonds effect is on).
  std::vector<double> bond_shear[3];         // u_b, total tangential displacement since bonding
  std::vector<double> bond_rest_gap;         // g_0
  // Bond::integrity: 1 intact, 0 broken or never bonded, in between a softening bond.
  std::vector<double> bond_integrity;
  std::vector<double> rolling[3];            // rolling moment on j (empty unless rolling is on)

  std::size_t size() const { return i.size(); }
  bool has_bonds() const { return !bond_integrity.empty(); }
  bool has_rolling() const { return !rolling[0].empty(); }

  // Rows to columns. `bonds` and `rolling` are parallel to `pairs` or empty (effect off).
  static PairTable from_rows(const std::vector<Pair>& pairs, const std::vector<Bond>& bonds,
                             const std::vector<Vec3>& rolling);
  std::vector<Pair> pair_rows() const;
  std::vector<Bond> bond_rows() const;          // empty without bonds
  std::vector<Vec3> rolling_rows() const;       // empty without rolling
  std::int64_t intact_bonds() const;  // bonds with integrity > 0
  std::size_t memory_bytes() const;
};

}  // namespace grainbank::dem
