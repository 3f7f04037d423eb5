// Verlet-list construction for a skewed periodic cell: binning in reduced coordinates with bins whose
// perpendicular width is at least the cut-off, so any pair within range sits in neighbouring bins
// whatever the tilt of the cell.
#pragma once
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "dem_sampler/cell/cell_state.hpp"

namespace grainbank::dem {

// The cell has become too thin for a unique periodic image within interaction range.
class CellTooThinError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class VerletListBuilder {
 public:
  // Fills `pairs` with every (i < j, image of j) whose centre distance is below R_i + R_j + skin,
  // sorted by (i, j), with zero history. `s` must be wrapped into [0,1)³.
  // Throws CellTooThinError when a cell width falls below twice the largest cut-off.
  void build(const Mat3& h, const std::vector<Vec3>& s, const std::vector<double>& radius, double max_radius,
             double skin, std::vector<Pair>& pairs);

 private:
  std::vector<std::uint32_t> bin_start_, sorted_;
};

}  // namespace grainbank::dem
