// The two side walls of a channel, parallel to the plane of the flow: the quasi-2D flume of a
// laboratory collapse or avalanche, seen by a plane-strain model.
//
// Why: a plane-strain flow has no side walls, but a flume of width W has two, and they take
// friction. Granular collapses in channels depend on it: the prefactors of the runout laws differ
// between narrow and wide channels (Balmforth & Kerswell 2005, J. Fluid Mech. 538:399), collapses of
// truly two-dimensional grains (aluminium rods, no side walls) run out ΔL/L0 ≈ 3.25 a^0.96 at
// 0.65 < a < 1.5 (arXiv:1512.05180), far beyond the 1.2 a of quasi-2D flumes, and a constant-friction
// continuum reproduces flume collapses once the side walls' friction is in it (Rousseau et al. 2023,
// J. Fluid Mech., "Revisiting the role of friction coefficients in granular collapses").
//
// The walls hold the material in plane strain, so each carries the out-of-plane normal stress
// −σ_zz, and Coulomb friction μ_w on both acts on the material between them, per unit volume,
// against its in-plane motion, at most
//   f = 2 μ_w max(0, −σ_zz) / W,
// the side-wall friction of flume models (as in Jop, Forterre & Pouliquen 2005, J. Fluid Mech.
// 541:167), with the out-of-plane stress the plane-strain law carries instead of an assumed
// earth-pressure coefficient.
//
// On the grid, as a Coulomb contact: node i gathers its capacity F_i = Σ_p N_ip V_p f_p; the friction
// takes from the node's updated velocity v_i' = v_i + Δt a_i at most Δt F_i / m_i of its magnitude,
// against its direction. It so never reverses a motion, and it holds a material at rest whose other
// forces stay below the walls' friction (static friction).
#pragma once
#include <vector>

#include "mpm_solver/core/bspline.hpp"
#include "mpm_solver/core/grid.hpp"
#include "mpm_solver/core/material_point.hpp"

namespace grainbank::mpm {

struct ChannelWalls {
  double width;     // W, the distance between the walls [m]
  double friction;  // μ_w, the Coulomb friction of the material on a wall

  // Throws std::invalid_argument unless width > 0 and friction ≥ 0, both finite.
  ChannelWalls(double width, double friction);

  // The walls' friction on a point per unit of its volume, at most [N/m³].
  double friction_per_volume(const PointStress& stress) const;
};

// Applies the walls' friction to the nodal accelerations of `grid` after update_grid.
void apply_channel_walls(Grid& grid, const std::vector<MaterialPoint>& points, const std::vector<Stencil>& stencils,
                         const ChannelWalls& walls, double dt);

}  // namespace grainbank::mpm
