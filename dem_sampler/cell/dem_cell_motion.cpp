// Velocity Verlet for the spheres' fluctuations (see dem_cell.hpp): the kicks and the drift,
// vectorized over spheres as the force loop is over pairs (`omp simd` on plain 3-vectors, sphere
// arrays read as flat x, y, z).
#include <algorithm>
#include <cmath>

#include "dem_sampler/cell/dem_cell.hpp"
#include "dem_sampler/cell/lane_vector.hpp"

namespace grainbank::dem {
namespace {

// Cundall local damping (preparation only): each component of a force or torque loses α of its
// magnitude against the motion, so quasi-static relaxation converges faster.
double damped(double f, double v, double alpha) {
  return f - alpha * std::abs(f) * (v > 0 ? 1.0 : (v < 0 ? -1.0 : 0.0));
}
LaneVec locally_damped(const LaneVec& f, const LaneVec& v, double alpha) {
  return {damped(f.x, v.x, alpha), damped(f.y, v.y, alpha), damped(f.z, v.z, alpha)};
}

// The sphere arrays one kick reads and writes.
struct Kick {
  double *u, *omega;
  const double *force, *torque, *inv_mass, *inv_inertia;
  double half_dt, alpha;
  Mat3 Lt;  // Lᵀ of the current velocity gradient: m dv'/dt = f - m Lᵀ v'

  // Half a velocity-Verlet kick of sphere p.
  template <bool Damped>
  void apply(std::size_t p) const {
    LaneVec f = load_lane(force, p), torque = load_lane(this->torque, p);
    const LaneVec v = load_lane(u, p), w = load_lane(omega, p);
    if constexpr (Damped) {
      f = locally_damped(f, v, alpha);
      torque = locally_damped(torque, w, alpha);
    }
    store_lane(u, p, v + half_dt * (f * inv_mass[p] - times(Lt, v)));
    store_lane(omega, p, w + half_dt * inv_inertia[p] * torque);
  }
};

}  // namespace

template <bool Damped>
GRAINBANK_VECTOR_LOOP double DemCell::kick_and_drift(double dt, const Mat3& L, const Mat3& h_mid_inv, const Mat3& h_new) {
  const Kick kick{u_.data()->data(), omega_.data()->data(), force_.data()->data(), torque_.data()->data(),
                  inv_mass_.data(), inv_inertia_.data(), 0.5 * dt, local_damping_, L.transpose()};
  double *s = s_.data()->data(), *x = x_.data()->data();
  const double* s_build = s_build_.data()->data();
  double max_displacement2 = 0;
  const std::size_t n = radius_.size();
#pragma omp simd reduction(max : max_displacement2)
  for (std::size_t p = 0; p < n; ++p) {
    kick.apply<Damped>(p);
    const LaneVec s_new = load_lane(s, p) + dt * times(h_mid_inv, load_lane(kick.u, p));
    store_lane(s, p, s_new);
    store_lane(x, p, times(h_new, s_new));
    max_displacement2 = std::max(max_displacement2, squared_norm(times(h_new, s_new - load_lane(s_build, p))));
  }
  return max_displacement2;
}

template <bool Damped>
GRAINBANK_VECTOR_LOOP void DemCell::kick(double half_dt, const Mat3& L) {
  const Kick kick{u_.data()->data(), omega_.data()->data(), force_.data()->data(), torque_.data()->data(),
                  inv_mass_.data(), inv_inertia_.data(), half_dt, local_damping_, L.transpose()};
  const std::size_t n = radius_.size();
#pragma omp simd
  for (std::size_t p = 0; p < n; ++p) kick.apply<Damped>(p);
}

template double DemCell::kick_and_drift<true>(double, const Mat3&, const Mat3&, const Mat3&);
template double DemCell::kick_and_drift<false>(double, const Mat3&, const Mat3&, const Mat3&);
template void DemCell::kick<true>(double, const Mat3&);
template void DemCell::kick<false>(double, const Mat3&);

}  // namespace grainbank::dem
