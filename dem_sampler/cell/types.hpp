// Small fixed-size tensor types shared by the DEM cell. SI units, double precision.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/LU>

namespace grainbank::dem {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

// Angular velocity of the rigid spin W = (L - Lᵀ)/2 of a velocity gradient L: W x = w × x.
inline Vec3 spin_vector(const Mat3& L) {
  return 0.5 * Vec3(L(2, 1) - L(1, 2), L(0, 2) - L(2, 0), L(1, 0) - L(0, 1));
}

}  // namespace grainbank::dem
