// Small fixed-size tensor types of the 2D plane-strain MPM. SI units, double precision.
#pragma once
#include <Eigen/Core>
#include <Eigen/LU>

namespace grainbank::mpm {

using Vec2 = Eigen::Vector2d;
using Mat2 = Eigen::Matrix2d;

// Cauchy stress of a plane-strain point, tension-positive: the in-plane block and σ_zz (which the
// momentum balance does not use but a 3D law needs).
struct PointStress {
  Mat2 in_plane = Mat2::Zero();
  double zz = 0;
};

// p = -tr σ / 3 (compression positive) and q = sqrt(3/2 s:s) of a plane-strain stress.
inline double pressure_of(const PointStress& s) { return -(s.in_plane.trace() + s.zz) / 3; }
double deviatoric_stress_of(const PointStress& s);

}  // namespace grainbank::mpm
