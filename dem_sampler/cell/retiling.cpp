#include "dem_sampler/cell/retiling.hpp"

#include <algorithm>
#include <numeric>
#include <stdexcept>

#include "dem_sampler/cell/periodic_cell.hpp"

namespace grainbank::dem {
namespace {

// The two copies of a list of reduced positions: s with s_axis halved, and that plus ½ along axis
// (one old cell vector further).
std::vector<Vec3> doubled_positions(const std::vector<Vec3>& s, int axis) {
  const std::size_t n = s.size();
  std::vector<Vec3> out(2 * n);
  for (std::size_t p = 0; p < n; ++p) {
    out[p] = s[p];
    out[p][axis] = 0.5 * s[p][axis];
    out[p + n] = s[p];
    out[p + n][axis] = 0.5 * (s[p][axis] + 1);
  }
  return out;
}

template <class T>
std::vector<T> twice(const std::vector<T>& v) {
  std::vector<T> out(v);
  out.insert(out.end(), v.begin(), v.end());
  return out;
}

}  // namespace

int thinnest_axis(const Mat3& h) {
  int axis = 0;
  perpendicular_widths(h).minCoeff(&axis);
  return axis;
}

CellState doubled_along(const CellState& st, int axis) {
  if (axis < 0 || axis > 2) throw std::invalid_argument("re-tiling: the axis must be 0, 1 or 2");
  if (st.reduced_position_at_list_build.empty())
    throw std::invalid_argument("re-tiling: the state has no Verlet list yet (a fresh state)");
  const std::size_t n = st.radius.size();
  Mat3 m = Mat3::Identity();
  m(axis, axis) = 2;

  CellState out;
  out.h = st.h * m;
  out.h_reference = st.h_reference * m;  // F = h h_ref⁻¹ is unchanged
  out.time = st.time;
  out.radius = twice(st.radius);
  out.reduced_position = doubled_positions(st.reduced_position, axis);
  out.velocity = twice(st.velocity);
  out.angular_velocity = twice(st.angular_velocity);
  out.force = twice(st.force);
  out.torque = twice(st.torque);
  out.initial_bond_count = 2 * st.initial_bond_count;
  out.h_at_list_build = st.h_at_list_build * m;
  out.reduced_position_at_list_build = doubled_positions(st.reduced_position_at_list_build, axis);
  out.last_stress = st.last_stress;  // the same infinite packing: twice the force sum over twice the volume
  out.last_active_pairs = 2 * st.last_active_pairs;
  out.last_pair_force_sum = 2 * st.last_pair_force_sum;

  // Pair (i, j, image ν) of the old cell joins copy c of i to the point x_j + h ν + c a_axis, which is
  // copy c_j of j shifted by the supercell image ν' with ν + c e_axis = c_j e_axis + M ν'. When copy
  // 1 of i meets copy 0 of j the pair is listed the other way round (i < j), so its history, which
  // is carried by j, changes sign with the branch vector.
  const bool bonds = !st.bonds.empty(), rolling = !st.rolling_moment.empty();
  std::vector<Pair> pairs;
  std::vector<Bond> bond;
  std::vector<Vec3> moment;
  pairs.reserve(2 * st.pairs.size());
  for (int c = 0; c < 2; ++c) {
    for (std::size_t k = 0; k < st.pairs.size(); ++k) {
      Pair p = st.pairs[k];
      Eigen::Vector3i image = shift_vector(static_cast<int>(p.image));
      const int t = image[axis] + c;
      const int c_j = ((t % 2) + 2) % 2;
      image[axis] = (t - c_j) / 2;
      std::uint32_t i = p.i + static_cast<std::uint32_t>(c * n), j = p.j + static_cast<std::uint32_t>(c_j * n);
      double sign = 1;
      if (i > j) {
        std::swap(i, j);
        image = -image;
        sign = -1;
      }
      p.i = i;
      p.j = j;
      p.image = static_cast<std::uint32_t>(shift_code(image));
      p.ft *= sign;
      pairs.push_back(p);
      if (bonds) {
        Bond b = st.bonds[k];
        b.shear_displacement *= sign;
        bond.push_back(b);
      }
      if (rolling) moment.push_back(sign * st.rolling_moment[k]);
    }
  }
  std::vector<std::size_t> order(pairs.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return pairs[a].i != pairs[b].i ? pairs[a].i < pairs[b].i : pairs[a].j < pairs[b].j;
  });
  for (std::size_t k : order) {
    out.pairs.push_back(pairs[k]);
    if (bonds) out.bonds.push_back(bond[k]);
    if (rolling) out.rolling_moment.push_back(moment[k]);
  }
  return out;
}

}  // namespace grainbank::dem
