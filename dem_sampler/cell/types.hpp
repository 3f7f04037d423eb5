// Small fixed-size tensor types shared by the DEM cell. SI units, double precision.
#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/LU>

namespace grainbank::dem {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

}  // namespace grainbank::dem
