#include "mpm_solver/core/seeding.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace grainbank::mpm {

Polyline rectangle(const Vec2& lower, const Vec2& upper) {
  return Polyline{{lower, Vec2(upper.x(), lower.y()), upper, Vec2(lower.x(), upper.y())}, true};
}

std::size_t seed_region(Solver& solver, std::size_t law, const Polyline& region, int points_per_cell,
                        const Vec2& velocity) {
  if (points_per_cell < 1) throw std::invalid_argument("points_per_cell: expected an integer >= 1");
  if (!region.closed) throw std::invalid_argument("a material region must be a closed polygon");
  check(region);
  const Grid& grid = solver.grid();
  Vec2 lo = region.vertices.front(), hi = lo;
  for (const Vec2& v : region.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  if (!grid.contains(lo) || !(hi.x() <= grid.upper().x() && hi.y() <= grid.upper().y()))
    throw std::invalid_argument("the region reaches outside the grid");
  const double h = grid.cell_size(), spacing = h / points_per_cell;
  const auto first = [&](double x, double origin) { return static_cast<int>(std::floor((x - origin) / h)); };
  const int i0 = first(lo.x(), grid.lower().x()), i1 = std::min(first(hi.x(), grid.lower().x()), grid.cells_x() - 1);
  const int j0 = first(lo.y(), grid.lower().y()), j1 = std::min(first(hi.y(), grid.lower().y()), grid.cells_y() - 1);
  std::size_t added = 0;
  for (int j = j0; j <= j1; ++j)
    for (int b = 0; b < points_per_cell; ++b)
      for (int i = i0; i <= i1; ++i)
        for (int a = 0; a < points_per_cell; ++a) {
          const Vec2 x = grid.lower() + Vec2(i * h + (a + 0.5) * spacing, j * h + (b + 0.5) * spacing);
          if (!contains(region, x)) continue;
          solver.add_point(law, x, spacing * spacing, 0.5 * spacing, velocity);
          ++added;
        }
  return added;
}

}  // namespace grainbank::mpm
