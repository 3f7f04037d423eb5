// The regularization of softening materials: the velocity gradient that drives a point's law is the
// average of its neighbours' over a length ℓ set in the scene, not the gradient at the point alone.
//
// Why: a law that softens (a bonded DEM cell losing its bonds, seed Eq. 6) localizes its failure in
// a band one grid cell wide, so a local MPM converges to nothing as h → 0: a finer grid resolves more
// of the stress concentration at a cut's toe, and a thinner band dissipates less. The seed lists this
// mesh dependence as its open problem. Averaging the strain rate over ℓ gives the material an
// internal length (nonlocal averaging of the strain: Bažant & Jirásek 2002, J. Eng. Mech. 128:1119):
// a band narrower than ℓ drives its cells at the band's average rate, so failure spreads over ℓ
// whatever h. A DEM cell's damage lives in its bonds, out of reach of an average; its strain rate is
// what the MPM hands it.
//
// The average, for point p, over the points q of the same law (materials do not mix):
//   L̄_p = L_p + Σ_{q≠p} w(|x_p − x_q|) V_q (L_q − L_p) / W,   W = max_p Σ_q w(|x_p − x_q|) V_q,
//   w(r) = (1 − r/ℓ)⁴ (1 + 4 r/ℓ) for r < ℓ, 0 beyond (Wendland's C² function).
// Why this form:
// - The weight is positive definite (its Fourier transform is positive; Wendland 1995, Adv. Comput.
//   Math. 4:389), so the averaging loses stiffness at short wavelengths but never turns it negative.
//   A truncated bell (1 − r²/ℓ²)² is not (its transform changes sign): with it, an elastic column
//   regularized over 4 h does not settle (tests/mpm/nonlocal_average_test.cpp).
// - One normalization W for all points, the weight a point's neighbourhood lacks (at a free surface,
//   a wall, another material) kept by the point itself: the averaging is symmetric, V_p α_pq =
//   V_q α_qp (Borino, Failla & Parrinello 2003, Int. J. Solids Struct. 40:3621), so it neither makes
//   nor loses deformation (Σ V L̄ = Σ V L) and the regularized stiffness is symmetric. The classical
//   form, each point divided by its own neighbourhood's weight, averages a boundary point over the
//   body behind it only, and so drives it with motion that is not its own: in a live column on its
//   floor, the bottom row then carried half its geostatic stress, in horizontal tension, and its
//   bonds broke at the toe before the gate opened (docs/validation_cohesive.md, "Tried and not kept").
// - Uniform fields stay exact: the weights act on differences L_q − L_p.
// The price of the symmetric form: near a boundary the average is partly local, two-thirds at a
// corner (the toe of a cut) and nearly half along an edge, for ℓ = 8 h.
//
// What it does not do: the grid still moves with the local gradients, so a motion whose gradient
// averages to nearly zero over ℓ (a checkerboard of grid-cell scale) meets almost no stiffness, the
// known weakness of averaging the total strain (same review). The tests watch for such modes in an
// elastic column settling under gravity (tests/mpm/nonlocal_average_test.cpp).
#pragma once
#include <vector>

#include "mpm_solver/core/material_point.hpp"

namespace grainbank::mpm {

class NonlocalAverage {
 public:
  // Throws std::invalid_argument unless length > 0 and finite [m].
  explicit NonlocalAverage(double length);
  double length() const { return length_; }

  // Replaces every point's velocity_gradient by L̄ above, computed from the gradients on entry.
  void apply(std::vector<MaterialPoint>& points) const;

 private:
  double length_;
};

}  // namespace grainbank::mpm
