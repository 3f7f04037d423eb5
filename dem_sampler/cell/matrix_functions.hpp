// Exponential and logarithm of 3x3 matrices, for constant-velocity-gradient paths: a deformation
// increment F over Δt has the constant velocity gradient L = log(F)/Δt and h(t) = exp(L t) h(0).
// Scaling and squaring; accurate to round-off for the moderate arguments of a deformation step.
#pragma once
#include <cmath>
#include <stdexcept>

#include "dem_sampler/cell/types.hpp"

namespace grainbank::dem {

inline Mat3 matrix_exponential(const Mat3& a) {
  // Halve the argument until its norm is below 1/2; the series then converges in < 20 terms.
  const double norm = a.cwiseAbs().colwise().sum().maxCoeff();
  const int squarings = norm > 0.5 ? static_cast<int>(std::ceil(std::log2(norm / 0.5))) : 0;
  const Mat3 scaled = a / std::ldexp(1.0, squarings);
  Mat3 sum = Mat3::Identity(), term = Mat3::Identity();
  for (int k = 1; k < 30; ++k) {
    term = term * scaled / k;
    sum += term;
    if (term.cwiseAbs().maxCoeff() <= 1e-17 * sum.cwiseAbs().maxCoeff()) break;
  }
  for (int s = 0; s < squarings; ++s) sum = sum * sum;
  return sum;
}

// Principal logarithm of F (det F > 0, no rotation by π): square roots (Denman-Beavers) until F is
// near I, then the series log F = 2 Σ Z^(2k+1)/(2k+1), Z = (F - I)(F + I)⁻¹.
inline Mat3 matrix_logarithm(const Mat3& f) {
  if (!f.allFinite() || !(f.determinant() > 0))
    throw std::invalid_argument("matrix_logarithm: expected a finite matrix with a positive determinant");
  Mat3 x = f;
  int roots = 0;
  while ((x - Mat3::Identity()).norm() > 0.25) {
    if (++roots > 60) throw std::invalid_argument("matrix_logarithm: no principal logarithm (rotation by π?)");
    Mat3 y = x, z = Mat3::Identity();
    for (int it = 0; it < 100; ++it) {
      const Mat3 y_next = 0.5 * (y + z.inverse());
      z = 0.5 * (z + y.inverse());
      const bool converged = (y_next - y).norm() <= 1e-15 * y_next.norm();
      y = y_next;
      if (converged) break;
    }
    x = y;
  }
  const Mat3 z = (x - Mat3::Identity()) * (x + Mat3::Identity()).inverse();
  const Mat3 z2 = z * z;
  Mat3 term = z, sum = z;
  for (int k = 1; k < 60; ++k) {
    term = term * z2;
    const Mat3 add = term / (2 * k + 1);
    sum += add;
    if (add.cwiseAbs().maxCoeff() <= 1e-18 * sum.cwiseAbs().maxCoeff()) break;
  }
  return std::ldexp(2.0, roots) * sum;
}

}  // namespace grainbank::dem
