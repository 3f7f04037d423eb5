#include "mpm_solver/core/homogeneous_drive.hpp"

#include <algorithm>

namespace grainbank::mpm {

HomogeneousDrive servoed_drive(const HomogeneousDrive& drive, const std::vector<MaterialPoint>& points, double dt,
                               double& integral) {
  if (!drive.normal_stress || points.empty()) return drive;
  double volume = 0, weighted_normal = 0;
  for (const MaterialPoint& p : points) {
    volume += p.volume;
    weighted_normal += p.volume * p.stress.in_plane(1, 1);
  }
  const NormalStressControl& control = *drive.normal_stress;
  HomogeneousDrive servoed = drive;
  servoed.velocity_gradient(1, 1) = 0;
  const double limit = servoed.velocity_gradient.norm();
  const double error = (-control.stress - weighted_normal / volume) / control.stress;
  integral = std::clamp(integral + control.response_rate * error * dt / control.integral_time, -limit, limit);
  servoed.velocity_gradient(1, 1) = std::clamp(control.response_rate * error + integral, -limit, limit);
  return servoed;
}

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
