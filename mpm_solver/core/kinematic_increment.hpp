// What a constitutive law is driven through in one call: the deformation increment F_inc, the time
// dt it took and the constant velocity gradient L that produces it, F_inc = exp(L dt). Built one way
// everywhere (an MPM step, skipped steps composed, a sampler path, an audit replay), so that a law,
// its rate-dependent parts (the DEM cell's sub-steps, the rate in a lookup key, seed Eq. 4) and the
// library it is compared with all see the same motion at the same pace.
#pragma once
#include "dem_sampler/cell/types.hpp"
#include "mpm_solver/core/types.hpp"

namespace grainbank::mpm {

struct KinematicIncrement {
  Mat2 F = Mat2::Identity();  // F_inc, in-plane (plane strain: the z row is the identity's)
  Mat2 L = Mat2::Zero();      // [1/s]
  double dt = 0;              // [s]

  // The increment of a step at constant L: F_inc = exp(L dt).
  static KinematicIncrement of_velocity_gradient(const Mat2& L, double dt);
  // The increment F_inc over dt, with L = log(F_inc) / dt. Throws std::invalid_argument when
  // F_inc has no principal logarithm (det ≤ 0, or a rotation by π) or dt ≤ 0.
  static KinematicIncrement of_deformation(const Mat2& F_inc, double dt);

  // |log F_inc|: the size of the increment, stretch and rotation together.
  double size() const { return (L * dt).norm(); }
  // Its small-strain and spin parts, dε = sym(L) dt and dω = skew(L) dt.
  Mat2 strain() const { return 0.5 * (L + L.transpose()) * dt; }
  Mat2 spin() const { return 0.5 * (L - L.transpose()) * dt; }
};

// In-plane F_inc embedded in 3D for a DEM cell: [[F, 0], [0, 1]] (plane strain).
dem::Mat3 embed_plane_strain(const Mat2& F_inc);

}  // namespace grainbank::mpm
