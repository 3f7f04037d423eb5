#include "mpm_solver/core/channel_walls.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace grainbank::mpm {

ChannelWalls::ChannelWalls(double width_, double friction_) : width(width_), friction(friction_) {
  if (!(std::isfinite(width) && width > 0))
    throw std::invalid_argument("channel walls: expected a finite width > 0 m, got " + std::to_string(width));
  if (!(std::isfinite(friction) && friction >= 0))
    throw std::invalid_argument("channel walls: expected a finite friction >= 0, got " + std::to_string(friction));
}

double ChannelWalls::friction_per_volume(const PointStress& stress) const {
  return 2 * friction * std::max(0.0, -stress.zz) / width;
}

void apply_channel_walls(Grid& grid, const std::vector<MaterialPoint>& points, const std::vector<Stencil>& stencils,
                         const ChannelWalls& walls, double dt) {
  // Serial: one scalar per node and point, cheap beside the transfers, and no per-thread buffers.
  std::vector<double> capacity(grid.node_count(), 0.0);
  const std::size_t stride = grid.nodes_x();
  for (std::size_t p = 0; p < points.size(); ++p) {
    const double f = points[p].volume * walls.friction_per_volume(points[p].stress);
    if (f == 0) continue;
    const Stencil& s = stencils[p];
    for (int b = 0; b < 4; ++b)
      for (int i = 0; i < 4; ++i) capacity[s.first_node + b * stride + i] += s.wx[i] * s.wy[b] * f;
  }
  for (std::size_t k = 0; k < capacity.size(); ++k) {
    const double m = grid.sums.mass[k];
    if (!(m > 0) || capacity[k] == 0) continue;
    const Vec2 updated = grid.velocity[k] + dt * grid.acceleration[k];
    const double speed = updated.norm();
    if (speed == 0) continue;
    const double taken = std::min(speed, dt * capacity[k] / m);
    grid.acceleration[k] -= (taken / (dt * speed)) * updated;
  }
}

}  // namespace grainbank::mpm
