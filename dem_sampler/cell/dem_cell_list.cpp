// The cell's Verlet list and the changes of its basis: when the list is stale, its rebuild (pair
// histories and bonds carried over), and the flips and re-tiling that keep a sheared cell from
// becoming too skewed or too thin.

#include "dem_sampler/cell/dem_cell.hpp"
#include "dem_sampler/cell/periodic_cell.hpp"
#include "dem_sampler/cell/retiling.hpp"

namespace grainbank::dem {

bool DemCell::list_is_stale(double max_displacement2) const {
  // A pair's separation changes by (h h_b⁻¹ - I) ℓ_b (affine, |ℓ_b| < cut-off) plus the difference of
  // the two spheres' fluctuation displacements h (s - s_b): rebuild before the sum can exceed the skin.
  const double cutoff = 2 * max_radius_ + skin_;
  const double affine = (h_ * h_build_.inverse() - Mat3::Identity()).norm() * cutoff;
  if (affine >= skin_) return true;
  const double allowed = 0.5 * (skin_ - affine);
  return max_displacement2 > allowed * allowed;
}

void DemCell::rebuild_list() {
  const std::size_t n = radius_.size();
  for (std::size_t p = 0; p < n; ++p) s_[p] = wrapped_into_cell(s_[p]);
  builder_.build(h_, s_, radius_, max_radius_, skin_, scratch_pairs_);

  // Carry the history of surviving pairs (both lists sorted by (i, j)). Intact bonds stretched beyond
  // the Verlet range stay listed, with the image of j closest to i; they are collected apart and
  // merged afterwards so the new list is not reallocated while it is walked.
  const std::vector<Pair> old_pairs = pairs_.pair_rows();
  const std::vector<Bond> old_bonds = pairs_.bond_rows();
  const std::vector<Vec3> old_rolling = pairs_.rolling_rows();
  std::vector<Bond> new_bonds(material_.effects.bonds ? scratch_pairs_.size() : 0);
  std::vector<Vec3> new_rolling(material_.effects.rolling ? scratch_pairs_.size() : 0, Vec3::Zero());
  std::vector<std::size_t> kept;  // indices into the old list
  auto key = [](const Pair& p) { return (static_cast<std::uint64_t>(p.i) << 32) | p.j; };
  auto keep_if_bonded = [&](std::size_t k_old) {
    if (!old_bonds.empty() && old_bonds[k_old].intact()) kept.push_back(k_old);
  };
  std::size_t k_old = 0;
  for (std::size_t k = 0; k < scratch_pairs_.size(); ++k) {
    Pair& p = scratch_pairs_[k];
    p.damping = coef_.pair_damping(mass_[p.i], mass_[p.j]);
    for (; k_old < old_pairs.size() && key(old_pairs[k_old]) < key(p); ++k_old) keep_if_bonded(k_old);
    if (k_old < old_pairs.size() && key(old_pairs[k_old]) == key(p)) {
      p.ft = old_pairs[k_old].ft;
      if (!old_bonds.empty()) new_bonds[k] = old_bonds[k_old];
      if (!old_rolling.empty()) new_rolling[k] = old_rolling[k_old];
      ++k_old;
    }
  }
  for (; k_old < old_pairs.size(); ++k_old) keep_if_bonded(k_old);
  if (!kept.empty()) {
    std::vector<Pair> merged;
    std::vector<Bond> merged_bonds;
    std::vector<Vec3> merged_rolling;
    merged.reserve(scratch_pairs_.size() + kept.size());
    std::size_t a = 0;
    auto take_new = [&] {
      merged.push_back(scratch_pairs_[a]);
      merged_bonds.push_back(new_bonds[a]);
      if (!new_rolling.empty()) merged_rolling.push_back(new_rolling[a]);
      ++a;
    };
    for (std::size_t k_kept : kept) {
      Pair out_of_range = old_pairs[k_kept];
      out_of_range.image = static_cast<std::uint32_t>(closest_image(out_of_range.i, out_of_range.j));
      while (a < scratch_pairs_.size() && key(scratch_pairs_[a]) < key(out_of_range)) take_new();
      merged.push_back(out_of_range);
      merged_bonds.push_back(old_bonds[k_kept]);
      if (!new_rolling.empty()) merged_rolling.push_back(old_rolling[k_kept]);
    }
    while (a < scratch_pairs_.size()) take_new();
    scratch_pairs_.swap(merged);
    new_bonds.swap(merged_bonds);
    new_rolling.swap(merged_rolling);
  }
  pairs_ = PairTable::from_rows(scratch_pairs_, new_bonds, new_rolling);
  h_build_ = h_;
  s_build_ = s_;
  ++list_builds_;
}

int DemCell::closest_image(std::uint32_t i, std::uint32_t j) const {
  int best = kNoShift;
  double best_d2 = std::numeric_limits<double>::max();
  for (int code = 0; code < kShiftCount; ++code) {
    const double d2 = (h_ * (s_[j] + shift_vector(code).cast<double>() - s_[i])).squaredNorm();
    if (d2 < best_d2) {
      best_d2 = d2;
      best = code;
    }
  }
  return best;
}

IntMat3 DemCell::reduce_if_needed() {
  if (!needs_reduction(h_)) return IntMat3::Identity();
  Mat3 h = h_;
  const IntMat3 m = reduce_basis(h);
  const Mat3 md = m.cast<double>();
  const Mat3 m_inv = md.inverse();  // integer and exact: det M = ±1
  h_ = h;
  h_inv_ = h_.inverse();
  h_ref_ = h_ref_ * md;
  for (Vec3& s : s_) s = m_inv * s;
  for (Vec3& s : s_build_) s = m_inv * s;
  rebuild_list();
  update_positions();
  ++flips_;
  return m;
}

bool DemCell::due_to_retile() const {
  const double cutoff = 2 * max_radius_ + skin_;
  return perpendicular_widths(h_).minCoeff() < kRetileMargin * 2 * cutoff;
}

bool DemCell::thin_beyond_retiling_cap() const {
  return retiling_cap_ > 0 && retiling_cap_ < 2 * size() && due_to_retile();
}

Mat3 DemCell::retile_if_needed() {
  if (retiling_cap_ < 2 * size() || !due_to_retile()) return Mat3::Identity();
  const int axis = thinnest_axis(h_);
  const std::int64_t flips = flips_, list_builds = list_builds_;
  const double local_damping = local_damping_;
  const std::size_t cap = retiling_cap_;
  *this = DemCell(doubled_along(state(), axis), material_, skin_);
  flips_ = flips;
  list_builds_ = list_builds;
  local_damping_ = local_damping;
  retiling_cap_ = cap;
  Mat3 m = Mat3::Identity();
  m(axis, axis) = 2;
  return m;
}

}  // namespace grainbank::dem
