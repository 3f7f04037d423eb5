// Geometry of a tri-periodic cell. The cell matrix h has the three cell vectors as columns; a point
// with reduced coordinates s ∈ [0,1)³ sits at x = h s. Nothing here moves particles.
#pragma once
#include <cmath>

#include <Eigen/Core>

#include "dem_sampler/cell/types.hpp"

namespace grainbank::dem {

using IntMat3 = Eigen::Matrix3i;

inline double cell_volume(const Mat3& h) { return std::abs(h.determinant()); }

// Reduced coordinates s wrapped into [0, 1)³: the same point of the periodic cell.
inline Vec3 wrapped_into_cell(Vec3 s) {
  for (int a = 0; a < 3; ++a) {
    s[a] -= std::floor(s[a]);
    if (s[a] >= 1) s[a] = 0;  // floor of a value just below an integer can round up
  }
  return s;
}

// Distance between opposite faces, per cell vector: w_i = V / |a_j × a_k|.
Vec3 perpendicular_widths(const Mat3& h);

// True when some cell vector leans on another by more than half of it, i.e. when a LAMMPS/YADE
// style flip is due (|a_j·a_i| > ½ |a_i|²).
bool needs_reduction(const Mat3& h);

// Replaces h by an equivalent, less skewed basis h M of the same lattice (M integer, det M = ±1)
// and returns M. Pairwise size reduction; each operation strictly shortens a cell vector, so it ends.
IntMat3 reduce_basis(Mat3& h);

// Image shifts n ∈ {-1,0,1}³ are coded as (n0+1) + 3(n1+1) + 9(n2+1); 13 is "no shift".
constexpr int kNoShift = 13;
constexpr int kShiftCount = 27;
inline Eigen::Vector3i shift_vector(int code) {
  return {code % 3 - 1, (code / 3) % 3 - 1, code / 9 - 1};
}
inline int shift_code(const Eigen::Vector3i& n) { return (n[0] + 1) + 3 * (n[1] + 1) + 9 * (n[2] + 1); }

}  // namespace grainbank::dem
