// Uniform cubic B-spline shape functions on the regular grid (16 nodes per point, tensor product).
// Being C², they remove the cell-crossing instability of linear shape functions (seed §2.1).
#pragma once
#include <cmath>
#include <cstddef>

#include "mpm_solver/core/grid.hpp"

namespace grainbank::mpm {

// Weights of the 4×4 nodes around one point: node (a, b) of the stencil is stored at
// first_node + a + b · nodes_x, has N = wx[a] wy[b], ∇N = (gx[a] wy[b], wx[a] gy[b]) and lies at
// x_i − x_p = (dx[a], dy[b]) from the point.
struct Stencil {
  std::size_t first_node = 0;
  double wx[4], wy[4], gx[4], gy[4], dx[4], dy[4];
};

// APIC's inertia-like matrix D_p = Σ_i N_ip (x_i − x_p)(x_i − x_p)ᵀ = h²/3 I for every point: the
// uniform cubic B-splines reproduce quadratics (Σ_i N_i x_i² = x² + h²/3 in 1D), and the ghost ring
// keeps every stencil complete, up to the border of the grid.
inline double affine_inertia(double h) { return h * h / 3; }

// 1D cubic B-spline weights (and derivatives, already divided by h) of the four nodes
// floor(ξ) - 1 … floor(ξ) + 2 for a point at fractional offset f = ξ - floor(ξ) ∈ [0, 1).
inline void cubic_weights(double f, double inv_h, double w[4], double g[4]) {
  const double r = 1 - f;
  w[0] = r * r * r / 6;
  w[1] = 0.5 * f * f * f - f * f + 2.0 / 3;
  w[2] = 0.5 * r * r * r - r * r + 2.0 / 3;
  w[3] = f * f * f / 6;
  g[0] = -0.5 * r * r * inv_h;
  g[1] = (1.5 * f * f - 2 * f) * inv_h;
  g[2] = -(1.5 * r * r - 2 * r) * inv_h;
  g[3] = 0.5 * f * f * inv_h;
}

// The 1D cubic B-spline N(u) and its derivative dN/du at u = (x - x_node) / h (zero from |u| = 2 on).
struct SplineValue {
  double value, slope;
};
inline SplineValue cubic_bspline(double u) {
  const double a = std::abs(u), sign = u < 0 ? -1.0 : 1.0;
  if (a >= 2) return {0.0, 0.0};
  if (a >= 1) return {(2 - a) * (2 - a) * (2 - a) / 6, -0.5 * (2 - a) * (2 - a) * sign};
  return {0.5 * a * a * a - a * a + 2.0 / 3, (1.5 * a * a - 2 * a) * sign};
}

// The stencil of a point at x, which the grid must contain (ghost ring: base index ≥ -1).
inline Stencil stencil_at(const Grid& grid, const Vec2& x) {
  const double inv_h = 1 / grid.cell_size();
  const Vec2 xi = (x - grid.lower()) * inv_h;
  const double fx = std::floor(xi.x()), fy = std::floor(xi.y());
  Stencil s;
  // Cell i has nodes i-1 … i+2, i.e. storage columns i … i+3 with the ghost shift of one.
  s.first_node = static_cast<std::size_t>(fx) + static_cast<std::size_t>(fy) * grid.nodes_x();
  cubic_weights(xi.x() - fx, inv_h, s.wx, s.gx);
  cubic_weights(xi.y() - fy, inv_h, s.wy, s.gy);
  const double h = grid.cell_size();
  for (int a = 0; a < 4; ++a) {
    s.dx[a] = (a - 1 - (xi.x() - fx)) * h;
    s.dy[a] = (a - 1 - (xi.y() - fy)) * h;
  }
  return s;
}

}  // namespace grainbank::mpm
