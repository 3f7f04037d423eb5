#include "mpm_solver/core/types.hpp"

#include <cmath>

namespace grainbank::mpm {

double deviatoric_stress_of(const PointStress& s) {
  const double mean = -pressure_of(s);  // tension-positive mean stress
  const double dxx = s.in_plane(0, 0) - mean, dyy = s.in_plane(1, 1) - mean, dzz = s.zz - mean;
  const double sxy = 0.5 * (s.in_plane(0, 1) + s.in_plane(1, 0));
  return std::sqrt(1.5 * (dxx * dxx + dyy * dyy + dzz * dzz + 2 * sxy * sxy));
}

}  // namespace grainbank::mpm
