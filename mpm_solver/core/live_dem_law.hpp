// The seed's double-scale law (§3): every material point owns a periodic DEM cell, a deep copy of one
// template made when the point is created, and drives it through the point's deformation increment at
// every MPM step. The in-plane increment is embedded in 3D with the z row and column of the identity
// (plane strain); the cell is sub-stepped per seed Eq. 3 and returns the stress regressed over the last
// Q_σ of the step (seed Fig. 3), tension-positive. The point's volume follows the cell's |det h|.
#pragma once
#include <vector>

#include "cell/dem_cell.hpp"
#include "constitutive_law.hpp"

namespace grainbank::mpm {

struct LiveDemSettings {
  dem::Substepping substepping;  // Q_t, Q_n, Q_σ of seed Eq. 3 and Fig. 3
  double q_h = 0.01;             // Q_h of seed Eq. 4: cell walls move at most Q_h d_min per MPM step
};

// In-plane F_inc embedded in 3D: [[F, 0], [0, 1]].
dem::Mat3 embed_plane_strain(const Mat2& F_inc);

class LiveDemLaw : public ConstitutiveLaw {
 public:
  // Keeps the template's state; each point gets its own DemCell rebuilt from it (never shared).
  LiveDemLaw(const dem::DemCell& cell_template, LiveDemSettings settings);

  std::string name() const override { return "live"; }
  double density() const override { return density_; }
  std::size_t add_point(PointStress& initial_stress) override;
  void update(std::size_t slot, const Mat2& F_inc, double dt, PointStress& stress) override;
  double volume_ratio(std::size_t slot, const Mat2& F) const override;
  double p_wave_modulus(std::size_t slot) const override { return modulus_[slot]; }
  double time_step_limit(std::size_t slot, const Mat2& L) const override;
  double damage(std::size_t slot) const override { return damage_[slot]; }
  bool expensive() const override { return true; }

  const dem::DemCell& cell(std::size_t slot) const { return cells_[slot]; }
  // Replaces the cell of `slot` by one continuing from `state` (restart files).
  void restore_cell(std::size_t slot, dem::CellState state);

 private:
  // Voigt (affine) estimate of the cell's P-wave modulus from its current coordination and solid
  // fraction: K = φ Z k_n / (12 π R), G = φ Z (2 k_n + 3 k_t) / (60 π R). An upper bound, so the CFL
  // step it gives is safe.
  double voigt_modulus(const dem::CellMeasures& m) const;

  dem::CellState template_state_;
  dem::Material material_;
  double skin_;
  LiveDemSettings settings_;
  double density_, mean_radius_, min_diameter_, template_volume_;
  std::vector<dem::DemCell> cells_;
  std::vector<double> modulus_, damage_;
};

}  // namespace grainbank::mpm
