// The force loop: geometry of every Verlet pair, the interaction law of interaction_law.hpp, and the
// Love-Weber sum of seed Eq. 2. Compiled once per set of effects, so an effect that is off costs no
// branch here, and stress is summed only at the steps where it is asked for.
#include "dem_sampler/cell/dem_cell.hpp"

namespace grainbank::dem {

template <bool Bonds, bool Rolling, bool Measure>
void DemCell::compute_forces(double dt) {
  std::fill(force_.begin(), force_.end(), Vec3::Zero());
  std::fill(torque_.begin(), torque_.end(), Vec3::Zero());
  Mat3 love_weber = Mat3::Zero();
  double sum_force = 0;
  std::int64_t active = 0;
  const Mat3 L = L_;
  const Vec3 cell_spin = spin_vector(L);
  const std::size_t count = pairs_.size();
  for (std::size_t k = 0; k < count; ++k) {
    Pair& p = pairs_[k];
    const std::uint32_t i = p.i, j = p.j;
    const Vec3 l = x_[j] - x_[i] + shift_[p.image];  // branch vector ℓ from i to the image of j
    const double r2 = l.squaredNorm();
    const double ri = radius_[i], rj = radius_[j], rsum = ri + rj;
    const bool touching = r2 < rsum * rsum;
    bool bonded = false;
    if constexpr (Bonds) bonded = bonds_[k].intact;
    if (!touching && !bonded) {
      // Contact lost: forget its history (written only when there is some, to spare memory traffic).
      if (p.ft[0] != 0 || p.ft[1] != 0 || p.ft[2] != 0) p.ft.setZero();
      if constexpr (Rolling) rolling_[k].setZero();
      continue;
    }
    const double r = std::sqrt(r2);
    const Vec3 n = l * (1 / r);  // one division, not one per component
    const double gap = r - rsum;
    const double arm_i = ri + 0.5 * gap, arm_j = rj + 0.5 * gap;  // to the contact point
    const Vec3 wi = omega_[i] + cell_spin, wj = omega_[j] + cell_spin;
    // Velocity of j's contact point relative to i's: fluctuations, affine field L ℓ, and spins.
    const Vec3 v = u_[j] - u_[i] + L * l - (arm_i * wi + arm_j * wj).cross(n);
    const double vn = v.dot(n);
    const Vec3 slip = (v - vn * n) * dt;
    const double twist = 0.5 * dt * (wi + wj).dot(n);

    double fn = 0, fn_contact = 0;
    Vec3 ft = Vec3::Zero();
    if (touching) {
      fn_contact = contact_normal_force(coef_, gap, vn, p.damping);
      update_friction(coef_, n, twist, slip, fn_contact, p.ft);
      fn = fn_contact;
      ft = p.ft;
    } else {
      p.ft.setZero();
    }
    if constexpr (Bonds) {
      if (bonded) {
        const bool holds = add_bond_force(coef_, bonds_[k], gap, n, twist, slip, fn, ft);
        if (holds && !touching) fn -= p.damping * vn;  // the dashpot acts once per pair
        if (!holds && !touching) continue;
      }
    }
    const Vec3 f = fn * n + ft;  // force on j; i receives -f
    force_[j] += f;
    force_[i] -= f;
    const Vec3 n_x_ft = n.cross(ft);
    torque_[i] -= arm_i * n_x_ft;
    torque_[j] -= arm_j * n_x_ft;
    if constexpr (Rolling) {
      if (touching) {
        update_rolling_moment(coef_, n, twist, (wj - wi) * dt, ri * rj / rsum, fn_contact, rolling_[k]);
        torque_[j] += rolling_[k];
        torque_[i] -= rolling_[k];
      } else {
        rolling_[k].setZero();
      }
    }
    if constexpr (Measure) {
      love_weber.noalias() += f * l.transpose();
      sum_force += f.norm();
      ++active;
    }
  }
  if constexpr (Measure) {
    stress_ = -love_weber / cell_volume(h_);
    sum_pair_force_ = sum_force;
    active_pairs_ = active;
  }
}

void DemCell::compute_forces(bool measure, double dt) {
  const bool bonds = material_.effects.bonds, rolling = material_.effects.rolling;
  if (measure) {
    if (bonds && rolling) return compute_forces<true, true, true>(dt);
    if (bonds) return compute_forces<true, false, true>(dt);
    if (rolling) return compute_forces<false, true, true>(dt);
    return compute_forces<false, false, true>(dt);
  }
  if (bonds && rolling) return compute_forces<true, true, false>(dt);
  if (bonds) return compute_forces<true, false, false>(dt);
  if (rolling) return compute_forces<false, true, false>(dt);
  return compute_forces<false, false, false>(dt);
}

}  // namespace grainbank::dem
