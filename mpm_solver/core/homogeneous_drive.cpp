#include "mpm_solver/core/homogeneous_drive.hpp"

namespace grainbank::mpm {

void impose_homogeneous_velocity(Grid& grid, const HomogeneousDrive& drive) {
  for (int row = 0; row < grid.nodes_y(); ++row)
    for (int col = 0; col < grid.nodes_x(); ++col) {
      const std::size_t k = static_cast<std::size_t>(col) + static_cast<std::size_t>(row) * grid.nodes_x();
      // Node (col, row) sits at cell corner (col - 1, row - 1): the grid has a ring of ghost nodes.
      const Vec2 x = grid.lower() + grid.cell_size() * Vec2(col - 1, row - 1);
      grid.velocity[k] = drive.velocity_gradient * (x - drive.origin);
      grid.acceleration[k].setZero();
    }
}

}  // namespace grainbank::mpm
