// The particle-grid transfers of one MUSL step (seed §2.1), each a pass over points or nodes.
// Scatters (point → node) accumulate into one NodeSums per thread and are then reduced, so OpenMP
// threads never write the same node; gathers (node → point) only read the grid.
#pragma once
#include <cmath>
#include <optional>
#include <vector>

#include "mpm_solver/core/bspline.hpp"
#include "mpm_solver/core/material_point.hpp"

namespace grainbank::mpm {

// How velocities go from the points to the grid and back.
struct VelocityTransfer {
  enum class Kind {
    apic,       // affine PIC: conserves angular momentum; damps only what affine fields cannot carry
    apic_flip,  // APIC's affine B_p with the FLIP/PIC blend of v_p (Fei et al. 2021): no damping at rate 0
    flip_pic,   // the FLIP/PIC blend of the seed (§2.1), without affine velocities
  };
  // The default, APIC-FLIP at 5 PIC per second: APIC alone damps at every transfer, so its runouts
  // depend on Δt (issue 17); at rates of 0 to 1/s the elastic ringing of a settled granular column
  // never decays (its kinetic energy stays above 1e-4 of the peak), from 5/s on it does, while the
  // runout hardly depends on the rate (1.389 at 5/s, 1.384 at 20/s, L0/h = 10, when it was chosen).
  // Since stop 78 the fluctuations' rough part blends out at 50/s (noise_rate).
  Kind kind = Kind::apic_flip;
  // Blends only: the PIC fraction per unit time r [1/s], so that the damping does not depend on
  // the time step: a step of Δt keeps the share e^{−r Δt} of a point's fluctuation (what FLIP keeps
  // of v_p beyond the PIC velocity Σ N v_i') and blends in the PIC velocity for the rest. 0 = pure
  // FLIP, ∞ = pure PIC.
  double pic_rate = 5;
  // Blends only, optional: the rate r_n [1/s] for the fluctuation's rough part, what a round trip
  // through the grid does not bring back (blend_in_fluctuations); r applies to the part it does.
  // Unset: r_n = r, one blend. With more points than nodes the rough part is how a body's points
  // ring against each other without the grid resolving it, and the MUSL remap passes it into the
  // velocity gradient that loads the points' laws. At the default 50/s (APIC-FLIP's; the FLIP/PIC
  // blend of the seed keeps one rate) a cohesive column of live cells at two points per cell stands
  // where it does at one, instead of breaking its toe's bonds under that ringing (issue 18, stop 78).
  static constexpr double kDefaultNoiseRate = 50;
  std::optional<double> noise_rate = kDefaultNoiseRate;

  // Whether points carry the affine velocity B_p (APIC's P2G and B_p update).
  bool affine() const { return kind != Kind::flip_pic; }
  double pic_weight(double dt) const { return kind == Kind::apic ? 1.0 : -std::expm1(-pic_rate * dt); }
  // The share of a point's fluctuation a step of Δt keeps, e^{−r Δt} (0 under APIC), and of its
  // rough part, e^{−r_n Δt}.
  double kept_share(double dt) const { return 1 - pic_weight(dt); }
  double kept_rough_share(double dt) const {
    return kind == Kind::apic ? 0.0 : std::exp(-noise_rate.value_or(pic_rate) * dt);
  }
  // Whether the rough part has a rate of its own (then G2P leaves the blending to blend_in_fluctuations).
  bool splits_fluctuations() const { return kind != Kind::apic && noise_rate && *noise_rate != pic_rate; }
};

// Per-thread accumulators, sized to the grid.
struct ScatterBuffers {
  std::vector<NodeSums> per_thread;
  explicit ScatterBuffers(std::size_t nodes);
};

// Shape-function stencils of every point (the points must all lie inside the grid).
void compute_stencils(const Grid& grid, const std::vector<MaterialPoint>& points, std::vector<Stencil>& stencils);

// P2G: nodal mass, momentum and internal force: m_i v_i = Σ_p N_ip m_p (v_p + C_p (x_i − x_p)) with
// C_p = B_p D_p⁻¹ (zero under FLIP/PIC), f_i = -Σ_p V_p σ_p ∇N_ip.
void particles_to_grid(Grid& grid, const std::vector<MaterialPoint>& points, const std::vector<Stencil>& stencils,
                       ScatterBuffers& buffers);

// How an obstacle's contact on the point centred at x, touched from the side -normal, meets the grid:
// node i of the point's stencil (first_node + a + b · nodes_x) takes weight[b][a] = ω_i / Σ ω,
//   ω_i = -V/A Σ_k ∇N_i(x + k d n) · n,   k = 0, 1, … while x + k d n lies within 4h of x,
// the boundary weights that the points' own internal forces -Σ_p V_p σ_p ∇N_i(x_p) give a node at a
// face of the body, summed over a column of points of spacing d (the point's, V/A = d) standing on
// the point along n. A stress that is uniform in that column then balances the contact force at every
// node: the nodes below the face, which only the column's lowest points reach, take exactly the share
// those points' stress sends them. Spread instead with the shape functions at the touching point (the
// face's N_i, which the points' quadrature does not integrate exactly), a column at rest on a floor at
// two points per cell carried its lowest two rows of points at 109 % and 87 % of their overburden, a
// stress pattern the nodes cannot see and no transfer damps (stop 77). The weights sum to one, so the
// force is applied in full.
struct ContactSpread {
  std::size_t first_node = 0;
  double weight[4][4] = {};
};
ContactSpread contact_spread(const Grid& grid, const Vec2& x, const Vec2& normal, double spacing);

// The material's velocity where the contact acts, Σ_i ω_i (m_i v_i) / m_i from the grid after P2G: the
// velocity of the nodes the contact force drives, weighted as it drives them, so the power it puts
// into the grid is f · v, the work its spring stores and its dashpot dissipates. Under a FLIP blend a
// point's own v_p also holds fluctuations the grid does not see; they do not move the point (positions
// follow the grid), so a contact driven by them would do work on the grid that no displacement pays for.
Vec2 material_velocity(const Grid& grid, const ContactSpread& spread);

// f_i += ω_i f.
void add_contact_force(Grid& grid, const ContactSpread& spread, const Vec2& f);

// Nodal velocity v_i = q_i / m_i and acceleration a_i = f_i / m_i + g at nodes carrying mass.
void update_grid(Grid& grid, const Vec2& gravity);

// G2P with the updated nodal velocities v_i' = v_i + Δt a_i: the PIC velocity Σ N v_i' and the
// fluctuation d_p = v_p + Δt Σ N a_i − Σ N v_i', what FLIP keeps beyond it;
// v_p ← Σ N v_i' + e^{−r Δt} d_p, or, when the transfer splits its fluctuations, v_p ← Σ N v_i' and
// d_p into `fluctuations[p]` for blend_in_fluctuations. Affine transfers also set
// B_p ← Σ N v_i' (x_i − x_p)ᵀ.
// Positions by the standard MUSL update x_p += Δt Σ N v_i' (symplectic Euler: a point bouncing on
// a penalty obstacle neither gains nor loses energy on average).
void grid_to_particles(const Grid& grid, std::vector<MaterialPoint>& points, const std::vector<Stencil>& stencils,
                       double dt, const VelocityTransfer& transfer, std::vector<Vec2>& fluctuations);

// v_p += e^{−r Δt} s_p + e^{−r_n Δt} (d_p − s_p), with s_p = Σ_i N_ip d_i, d_i = Σ_p N_ip m_p d_p / m_i:
// the part of the fluctuation d_p that a round trip through the grid brings back, and the rough rest
// (in the spirit of Hammerquist & Nairn's XPIC, 2017). The rest carries no momentum,
// Σ_p m_p (d_p − s_p) = Σ m_p d_p − Σ_i m_i d_i = 0, so blending it out at any rate conserves
// momentum. Uses grid.sums.momentum as scratch: the MUSL remap that follows rebuilds it.
void blend_in_fluctuations(Grid& grid, std::vector<MaterialPoint>& points, const std::vector<Stencil>& stencils,
                           const std::vector<Vec2>& fluctuations, double dt, const VelocityTransfer& transfer,
                           ScatterBuffers& buffers);

// MUSL remap: nodal velocities again from the updated point velocities, by the same (affine)
// momentum transfer as P2G, so that the velocity gradient of the stress update sees them.
void remap_velocities(Grid& grid, const std::vector<MaterialPoint>& points, const std::vector<Stencil>& stencils,
                      ScatterBuffers& buffers);

// L_p = Σ_i v_i ⊗ ∇N_ip from the current nodal velocities.
Mat2 velocity_gradient(const Grid& grid, const Stencil& s);

}  // namespace grainbank::mpm
