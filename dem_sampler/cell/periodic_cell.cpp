#include "dem_sampler/cell/periodic_cell.hpp"

#include <cmath>

#include <Eigen/Geometry>

namespace grainbank::dem {

Vec3 perpendicular_widths(const Mat3& h) {
  const double v = cell_volume(h);
  Vec3 w;
  for (int i = 0; i < 3; ++i) {
    const Vec3 a = h.col((i + 1) % 3), b = h.col((i + 2) % 3);
    w[i] = v / a.cross(b).norm();
  }
  return w;
}

namespace {
// Strictly above one half, with a margin so that a cell sitting exactly on the flip point does not
// flip back and forth on round-off.
constexpr double kFlipThreshold = 0.5 + 1e-9;

double lean(const Mat3& h, int j, int i) { return h.col(j).dot(h.col(i)) / h.col(i).squaredNorm(); }
}  // namespace

bool needs_reduction(const Mat3& h) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (i != j && std::abs(lean(h, j, i)) > kFlipThreshold) return true;
  return false;
}

IntMat3 reduce_basis(Mat3& h) {
  IntMat3 m = IntMat3::Identity();
  bool changed = true;
  while (changed) {
    changed = false;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        if (i == j) continue;
        const double mu = lean(h, j, i);
        if (std::abs(mu) <= kFlipThreshold) continue;
        const int r = static_cast<int>(std::lround(mu));
        h.col(j) -= r * h.col(i);
        m.col(j) -= r * m.col(i);
        changed = true;
      }
  }
  return m;
}

}  // namespace grainbank::dem
