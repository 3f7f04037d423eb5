// A material point of the 2D plane-strain MPM. Mass, volume and forces are per unit thickness.
#pragma once
#include <cmath>
#include <cstdint>

#include "mpm_solver/core/types.hpp"

namespace grainbank::mpm {

struct MaterialPoint {
  std::uint32_t id = 0;        // stable across sorting (outputs, contact history, tracking)
  std::uint32_t law = 0;       // index of its constitutive law in the solver
  std::uint32_t slot = 0;      // its state inside that law
  double mass = 0;             // [kg/m]
  double initial_volume = 0;   // [m²]
  double volume = 0;           // [m²]
  double radius = 0;           // disk radius seen by obstacles: half the initial point spacing [m]
  Vec2 position = Vec2::Zero();
  Vec2 velocity = Vec2::Zero();
  // APIC's B_p = Σ_i N_ip v_i (x_i − x_p)ᵀ: with C_p = B_p D_p⁻¹ the point carries the affine
  // velocity field v_p + C_p (x − x_p) (Jiang et al. 2015). Zero under the FLIP/PIC blend.
  Mat2 affine_velocity = Mat2::Zero();
  Mat2 deformation_gradient = Mat2::Identity();
  // L of the last step, the one its law was driven with and F integrates: the grid's gradient at the
  // point, or its nonlocal average when the scene regularizes (nonlocal_average.hpp).
  Mat2 velocity_gradient = Mat2::Zero();
  // Motion too small to be worth a constitutive call (SolverSettings::skip_strain_increment): the
  // increments of the skipped steps composed, and the time they took; identity and 0 when nothing
  // is pending.
  Mat2 pending_increment = Mat2::Identity();
  double pending_time = 0;
  PointStress stress;
};

// Seed Eq. 5: ε̇_q = sqrt((L_xx - L_yy)² + (L_xy + L_yx)²).
inline double deviatoric_strain_rate(const Mat2& L) {
  const double a = L(0, 0) - L(1, 1), b = L(0, 1) + L(1, 0);
  return std::sqrt(a * a + b * b);
}

}  // namespace grainbank::mpm
