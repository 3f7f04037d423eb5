// The particle-grid transfers of one MUSL step (seed §2.1), each a pass over points or nodes.
// Scatters (point → node) accumulate into one NodeSums per thread and are then reduced, so OpenMP
// threads never write the same node; gathers (node → point) only read the grid.
#pragma once
#include <vector>

#include "bspline.hpp"
#include "material_point.hpp"

namespace grainbank::mpm {

// Per-thread accumulators, sized to the grid.
struct ScatterBuffers {
  std::vector<NodeSums> per_thread;
  explicit ScatterBuffers(std::size_t nodes);
};

// Shape-function stencils of every point (the points must all lie inside the grid).
void compute_stencils(const Grid& grid, const std::vector<MaterialPoint>& points, std::vector<Stencil>& stencils);

// P2G: nodal mass, momentum and force: f_i = Σ_p (-V_p σ_p ∇N_ip + N_ip f_ext,p).
void particles_to_grid(Grid& grid, const std::vector<MaterialPoint>& points, const std::vector<Stencil>& stencils,
                       ScatterBuffers& buffers);

// Nodal velocity v_i = q_i / m_i and acceleration a_i = f_i / m_i + g at nodes carrying mass.
void update_grid(Grid& grid, const Vec2& gravity);

// G2P: point velocities by the FLIP/PIC blend, v_p ← α (v_p + Δt Σ N a_i) + (1 - α) Σ N (v_i + Δt a_i),
// and positions by x_p += Δt Σ N (v_i + Δt a_i / 2), the trapezoidal rule in time (exact for a
// uniform acceleration such as free fall).
void grid_to_particles(const Grid& grid, std::vector<MaterialPoint>& points, const std::vector<Stencil>& stencils,
                       double dt, double flip);

// MUSL remap: nodal velocities again from the updated point momenta, so that the velocity gradient
// of the stress update sees the blended velocities.
void remap_velocities(Grid& grid, const std::vector<MaterialPoint>& points, const std::vector<Stencil>& stencils,
                      ScatterBuffers& buffers);

// L_p = Σ_i v_i ⊗ ∇N_ip from the current nodal velocities.
Mat2 velocity_gradient(const Grid& grid, const Stencil& s);

}  // namespace grainbank::mpm
