// A prescribed homogeneous deformation of the whole domain: every node moves with v_i = L (x_i - x_0)
// and has no acceleration. Cubic B-splines reproduce linear fields, so every point sees exactly this
// L: an element test of a constitutive law through the full MPM step (e.g. one live-DEM point driven
// along the same history as a stand-alone `dem_sampler run`).
#pragma once
#include "mpm_solver/core/grid.hpp"
#include "mpm_solver/core/types.hpp"

namespace grainbank::mpm {

struct HomogeneousDrive {
  Mat2 velocity_gradient = Mat2::Zero();  // L [1/s]
  Vec2 origin = Vec2::Zero();             // x_0, the point that stays put [m]
};

// Overwrites every node's velocity with L (x_i - x_0) and its acceleration with zero.
void impose_homogeneous_velocity(Grid& grid, const HomogeneousDrive& drive);

}  // namespace grainbank::mpm
