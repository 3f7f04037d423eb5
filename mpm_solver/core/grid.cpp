#include "mpm_solver/core/grid.hpp"

#include <cmath>
#include <stdexcept>

namespace grainbank::mpm {

void NodeSums::resize(std::size_t n) {
  mass.assign(n, 0.0);
  momentum.assign(n, Vec2::Zero());
  force.assign(n, Vec2::Zero());
}

void NodeSums::clear() {
  std::fill(mass.begin(), mass.end(), 0.0);
  std::fill(momentum.begin(), momentum.end(), Vec2::Zero());
  std::fill(force.begin(), force.end(), Vec2::Zero());
}

Grid::Grid(Vec2 origin, double cell_size, int cells_x, int cells_y)
    : origin_(origin), h_(cell_size), cells_x_(cells_x), cells_y_(cells_y) {
  if (!origin.allFinite() || !(cell_size > 0) || !std::isfinite(cell_size) || cells_x < 1 || cells_y < 1)
    throw std::invalid_argument("grid: expected a finite origin, cell_size > 0 and at least one cell per direction");
  sums.resize(node_count());
  velocity.assign(node_count(), Vec2::Zero());
  acceleration.assign(node_count(), Vec2::Zero());
}

bool Grid::contains(const Vec2& x) const {
  const Vec2 hi = upper();
  return x.x() >= origin_.x() && x.y() >= origin_.y() && x.x() < hi.x() && x.y() < hi.y();
}

std::size_t Grid::cell_index(const Vec2& x) const {
  const auto i = static_cast<std::size_t>((x.x() - origin_.x()) / h_);
  const auto j = static_cast<std::size_t>((x.y() - origin_.y()) / h_);
  return std::min<std::size_t>(i, cells_x_ - 1) + std::min<std::size_t>(j, cells_y_ - 1) * cells_x_;
}

}  // namespace grainbank::mpm
