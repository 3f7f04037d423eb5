// The complete state of a periodic DEM cell as plain data: enough to rebuild a DemCell that continues
// bit-for-bit (snapshots, templates, restarts, warm starts). Stores convert it; the engine owns none
// of their formats.
#pragma once
#include <cstdint>
#include <vector>

#include "dem_sampler/cell/types.hpp"

namespace grainbank::dem {

// One entry of the Verlet list: spheres i < j, the periodic image of j (shift code, see
// periodic_cell.hpp) and the interaction history carried across steps and list rebuilds.
struct Pair {
  std::uint32_t i = 0, j = 0;
  std::uint32_t image = 13;
  double damping = 0;  // normal dashpot c_n of this pair [N·s/m]
  Vec3 ft = Vec3::Zero();  // tangential contact spring force on j (Coulomb-capped)
};

// Bond attached to a Verlet pair (only stored when bonds are on).
struct Bond {
  Vec3 shear_displacement = Vec3::Zero();  // u_b: total tangential displacement since bonding
  double rest_gap = 0;                     // g_0: gap at bonding, so the bond is stress-free then
  // The share of its elastic forces the bond carries: 1 intact, 0 broken; in between only for a
  // softening bond past its yield surface (BondLaw::softening).
  double integrity = 0;
  bool intact() const { return integrity > 0; }
};

struct CellState {
  Mat3 h = Mat3::Identity();        // cell vectors (columns)
  Mat3 h_reference = Mat3::Identity();  // h at the reference configuration: F = h h_ref⁻¹
  double time = 0;
  std::vector<double> radius;
  std::vector<Vec3> reduced_position;     // s (not necessarily wrapped)
  std::vector<Vec3> velocity;             // fluctuating velocity v' = v - L x [m/s]
  std::vector<Vec3> angular_velocity;     // spin fluctuation ω' = ω - w(L), w the cell's spin [rad/s]
  std::vector<Vec3> force, torque;        // at the current positions (velocity Verlet needs them)
  std::vector<Pair> pairs;                // sorted by (i, j)
  std::vector<Bond> bonds;                // parallel to pairs, or empty when bonds are off
  std::vector<Vec3> rolling_moment;       // parallel to pairs, or empty when rolling is off
  std::int64_t initial_bond_count = 0;    // N_b(0) of seed Eq. 6
  Mat3 h_at_list_build = Mat3::Identity();  // Verlet bookkeeping: h and s at the last rebuild
  std::vector<Vec3> reduced_position_at_list_build;
  Mat3 last_stress = Mat3::Zero();          // tension-positive, at the last measured step
  std::int64_t last_active_pairs = 0;       // pairs carrying force, at the last measured step
  double last_pair_force_sum = 0;           // Σ |pair force|, at the last measured step
};

}  // namespace grainbank::dem
