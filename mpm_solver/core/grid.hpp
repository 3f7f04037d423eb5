// The regular background grid of the MPM: cells of side h covering [origin, origin + n h], plus one
// ring of ghost nodes outside. The ghost ring is the border treatment of the cubic B-splines: a point
// anywhere inside the covered box has all 4×4 nodes of its stencil, so the weights still sum to one
// and their gradients to zero (exact momentum conservation, no lost mass near the border). Walls are
// obstacles, not nodal constraints, so ghost nodes are ordinary free nodes.
#pragma once
#include <cstddef>
#include <vector>

#include "mpm_solver/core/types.hpp"

namespace grainbank::mpm {

// What particle-to-grid transfers accumulate at the nodes.
struct NodeSums {
  std::vector<double> mass;
  std::vector<Vec2> momentum, force;

  void resize(std::size_t n);
  void clear();
};

class Grid {
 public:
  // Throws std::invalid_argument unless cell_size > 0 and at least one cell in each direction.
  Grid(Vec2 origin, double cell_size, int cells_x, int cells_y);

  double cell_size() const { return h_; }
  int cells_x() const { return cells_x_; }
  int cells_y() const { return cells_y_; }
  Vec2 lower() const { return origin_; }
  Vec2 upper() const { return origin_ + h_ * Vec2(cells_x_, cells_y_); }
  // True when x lies in the covered box (where every stencil is complete).
  bool contains(const Vec2& x) const;

  // Nodes, ghost ring included: node (i, j) for i in [-1, cells_x + 1] is stored at
  // (i + 1) + (j + 1) nodes_x().
  int nodes_x() const { return cells_x_ + 3; }
  int nodes_y() const { return cells_y_ + 3; }
  std::size_t node_count() const { return static_cast<std::size_t>(nodes_x()) * nodes_y(); }
  // Index of the cell containing x (row-major, for sorting points); x must be contained.
  std::size_t cell_index(const Vec2& x) const;

  // Nodal fields of the current step.
  NodeSums sums;                        // mass, momentum and forces from the points
  std::vector<Vec2> velocity;           // momentum / mass at the start of the step (then after remap)
  std::vector<Vec2> acceleration;       // force / mass

 private:
  Vec2 origin_;
  double h_;
  int cells_x_, cells_y_;
};

}  // namespace grainbank::mpm
