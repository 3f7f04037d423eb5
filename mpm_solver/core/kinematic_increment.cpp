#include "mpm_solver/core/kinematic_increment.hpp"

#include <cmath>
#include <stdexcept>

#include "dem_sampler/cell/matrix_functions.hpp"

namespace grainbank::mpm {

namespace {
// exp(A) of a 2x2 matrix in closed form (Cayley–Hamilton): with A = t I + B, t = tr A / 2 and
// B² = q I, q = -det B, exp(A) = e^t (cosh √q I + sinh √q / √q B), cos/sin for q < 0. Every MPM
// point takes one per step, so no series.
Mat2 exponential(const Mat2& a) {
  const double t = 0.5 * a.trace();
  const Mat2 b = a - t * Mat2::Identity();
  const double q = b(0, 0) * b(0, 0) + b(0, 1) * b(1, 0);
  double c, f;  // cosh √q and sinh √q / √q, continued to q < 0
  if (std::abs(q) < 1e-6) {
    c = 1 + q / 2 * (1 + q / 12);
    f = 1 + q / 6 * (1 + q / 20);
  } else if (q > 0) {
    const double s = std::sqrt(q);
    c = std::cosh(s), f = std::sinh(s) / s;
  } else {
    const double r = std::sqrt(-q);
    c = std::cos(r), f = std::sin(r) / r;
  }
  return std::exp(t) * (c * Mat2::Identity() + f * b);
}
}  // namespace

dem::Mat3 embed_plane_strain(const Mat2& F_inc) {
  dem::Mat3 f = dem::Mat3::Identity();
  f.topLeftCorner<2, 2>() = F_inc;
  return f;
}

KinematicIncrement KinematicIncrement::of_velocity_gradient(const Mat2& L, double dt) {
  if (!(dt > 0)) throw std::invalid_argument("increment: expected a positive time step");
  return {exponential(L * dt), L, dt};
}

KinematicIncrement KinematicIncrement::of_deformation(const Mat2& F_inc, double dt) {
  if (!(dt > 0)) throw std::invalid_argument("increment: expected a positive time step");
  return {F_inc, Mat2(dem::matrix_logarithm(embed_plane_strain(F_inc)).topLeftCorner<2, 2>()) / dt, dt};
}

}  // namespace grainbank::mpm
