// A prescribed homogeneous deformation of the whole domain: every node moves with v_i = L (x_i - x_0)
// and has no acceleration. Cubic B-splines reproduce linear fields, so every point sees exactly this
// L: an element test of a constitutive law through the full MPM step (e.g. one live-DEM point driven
// along the same history as a stand-alone `dem_sampler run`).
#pragma once
#include <optional>
#include <vector>

#include "mpm_solver/core/grid.hpp"
#include "mpm_solver/core/material_point.hpp"
#include "mpm_solver/core/types.hpp"

namespace grainbank::mpm {

// σ_yy held at −stress instead of a prescribed L_yy: the constant-normal-stress shear of a
// rheometer (dem_sampler/cell/shear_rheometer.hpp), in which a granular material flows at its own
// friction and dilatancy, as it does under a free surface, rather than building pressure as it does
// at constant volume. A PI servo on e = (−stress − σ̄_yy) / stress, σ̄_yy the points' volume-weighted
// mean: L_yy = clamp(response_rate e + J, ±|L|), J += response_rate e Δt / integral_time, with |L|
// that of the other components. The integral J removes the offset a material that keeps building
// pressure as it shears would leave a proportional servo with. It is stable while one step's
// correction moves σ_yy by less than the error, M Δt response_rate < stress (M the constrained
// modulus): response_rate = 1 /s suits soft cells at 0.1 ms steps.
struct NormalStressControl {
  double stress = 0;           // P > 0, compression [Pa]
  double response_rate = 1;    // > 0 [1/s]
  double integral_time = 0.05; // > 0 [s]
};

struct HomogeneousDrive {
  Mat2 velocity_gradient = Mat2::Zero();  // L [1/s]; its L_yy is replaced when normal_stress is set
  Vec2 origin = Vec2::Zero();             // x_0, the point that stays put [m]
  std::optional<NormalStressControl> normal_stress;
};

// The drive of the next step of length dt: `drive` itself, or with L_yy servoed on the points'
// stresses, advancing the servo's integral J [1/s] (the solver keeps it, and restart files too).
HomogeneousDrive servoed_drive(const HomogeneousDrive& drive, const std::vector<MaterialPoint>& points, double dt,
                               double& integral);

// Overwrites every node's velocity with L (x_i - x_0) and its acceleration with zero.
void impose_homogeneous_velocity(Grid& grid, const HomogeneousDrive& drive);

}  // namespace grainbank::mpm
