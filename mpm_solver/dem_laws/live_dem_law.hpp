// The seed's double-scale law (§3): every material point owns a periodic DEM cell, a deep copy of one
// template made when the point is created, and drives it through the point's deformation increment at
// every MPM step. The in-plane increment is embedded in 3D with the z row and column of the identity
// (plane strain); the cell is sub-stepped per seed Eq. 3 and returns the stress regressed over the last
// Q_σ of the step (seed Fig. 3), tension-positive. The point's volume follows the cell's |det h|.
#pragma once
#include <vector>

#include "mpm_solver/core/constitutive_law.hpp"
#include "mpm_solver/core/dem_backed_law.hpp"
#include "mpm_solver/core/point_sharing.hpp"
#include "mpm_solver/dem_laws/live_cell_model.hpp"

namespace grainbank::mpm {

class LiveDemLaw : public ConstitutiveLaw, public DemBackedLaw, public PointSharing {
 public:
  // Keeps the template's state; each point gets its own DemCell rebuilt from it (never shared).
  LiveDemLaw(const dem::DemCell& cell_template, LiveDemSettings settings);

  std::string name() const override { return "live"; }
  double density() const override { return model_.density(); }
  std::size_t add_point(PointStress& initial_stress) override;
  void update(std::size_t slot, const KinematicIncrement& increment, const Mat2& F, PointStress& stress) override;
  double volume_ratio(std::size_t slot, double kinematic) const override;
  double p_wave_modulus(std::size_t slot) const override { return modulus_[slot]; }
  double time_step_limit(std::size_t slot, const Mat2& F, const Mat2& L) const override;
  double damage(std::size_t slot) const override { return damage_[slot]; }
  bool expensive() const override { return true; }
  // Every cell, as "cell_<slot>"; restoring replaces each point's cell by one continuing from it.
  void save_state(LawStateWriter& out) const override;
  void restore_state(LawStateReader& in) override;
  const DemBackedLaw* dem_backed() const override { return this; }
  // On several ranks, each point's cell is driven by one rank; the others keep its modulus, damage
  // and counters (the summary), and receive the cell itself only when they must write it.
  PointSharing* point_sharing() override { return this; }
  void write_summary(std::size_t slot, common::ByteWriter& out) const override;
  void read_summary(std::size_t slot, common::ByteReader& in) override;
  void write_point_state(std::size_t slot, common::ByteWriter& out) const override;
  void read_point_state(std::size_t slot, common::ByteReader& in) override;

  StressSource source(std::size_t) const override { return StressSource::live; }
  CouplingCounters point_counters(std::size_t slot) const override { return counters_[slot]; }
  const dem::DemCell* live_cell(std::size_t slot) const override { return &cells_[slot]; }
  const dem::DemCell& cell(std::size_t slot) const { return cells_[slot]; }

 private:
  void measure(std::size_t slot);

  LiveCellModel model_;
  std::vector<dem::DemCell> cells_;
  std::vector<CouplingCounters> counters_;  // re-tilings only: every step of a live point is live
  std::vector<double> modulus_, damage_;
};

}  // namespace grainbank::mpm
