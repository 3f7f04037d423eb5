// What every law that drives DEM cells at material points shares (live, hybrid): the template the
// cells are copied from, the plane-strain embedding of the MPM increment, the stress handed back to
// the MPM, the CFL modulus of a cell and seed Eq. 4. One place, so a hybrid point that turns live
// behaves exactly like a point of the live law.
#pragma once
#include "dem_sampler/cell/dem_cell.hpp"
#include "dem_sampler/cell/effective_medium.hpp"
#include "mpm_solver/core/coupling_status.hpp"
#include "mpm_solver/core/kinematic_increment.hpp"
#include "mpm_solver/core/types.hpp"

namespace grainbank::mpm {

struct LiveDemSettings {
  dem::Substepping substepping;  // Q_t, Q_n, Q_σ of seed Eq. 3 and Fig. 3
  double q_h = 0.01;             // Q_h of seed Eq. 4: cell walls move at most Q_h d_min per MPM step
  std::size_t max_spheres = 0;   // re-tiling cap of every cell (DemCell::set_retiling_cap; 0: off)
  bool regenerate_beyond_cap = false;  // past the cap: regenerate the cell (true) or let it stop (false)
};

// The MPM momentum balance needs a symmetric stress; Love–Weber stress is symmetric only at
// equilibrium of moments, so its symmetric part is taken (as the reference implementation does).
PointStress plane_stress_of(const dem::Mat3& stress);

class LiveCellModel {
 public:
  // Throws std::invalid_argument on a bad q_h.
  LiveCellModel(const dem::DemCell& cell_template, LiveDemSettings settings);

  const LiveDemSettings& settings() const { return settings_; }
  const dem::Material& material() const { return material_; }
  // Density of the cell (spheres and voids) and its volume at the template state.
  double density() const { return density_; }
  double template_volume() const { return template_volume_; }
  std::size_t template_size() const { return template_state_.radius.size(); }

  // A deep copy of the template, or a cell continuing from `state` (the point owns it); both re-tile
  // up to the settings' cap.
  dem::DemCell new_cell() const { return with_cap(dem::DemCell(template_state_, material_, skin_)); }
  dem::DemCell cell_from(dem::CellState state) const {
    return with_cap(dem::DemCell(std::move(state), material_, skin_));
  }

  // Drives the cell through the in-plane increment; returns its regressed 3D stress
  // (plane_stress_of gives the MPM's part of it). A cell due to re-tile beyond the cap is first
  // regenerated from the template (dem_sampler/cell/regeneration.hpp) when the settings say so.
  // Counts the cell's re-tilings and regenerations into `counters`.
  //
  // A dispersed cell (no contact, no bond, more than kDispersedVolumeRatio times the template's
  // volume: grains that flew apart, carrying no stress) takes no dilating increment (det F_inc > 1);
  // it holds as it is, and so does the volume of its point, until the point is compressed. Without
  // this, a fragment whose affine velocity APIC keeps alive (an isolated point keeps its B_p, so its
  // L never decays as a ballistic cloud's does) stretches its cell exponentially, to kilometres.
  // Each such increment counts in counters.dispersed_holds.
  dem::Mat3 advance(dem::DemCell& cell, const KinematicIncrement& increment, CouplingCounters& counters) const;
  static constexpr double kDispersedVolumeRatio = 100;
  // Counts the doublings of a cell that had `spheres_before` spheres into `counters` (for cells
  // driven other than by advance, e.g. a warm start's drive_to).
  static void count_retilings(std::size_t spheres_before, const dem::DemCell& cell, CouplingCounters& counters);

  // The volume of the material the cell stands for, relative to the template's: det F of the cell
  // over the template's. Re-tiling and regeneration both keep a cell's F, so neither moves it.
  double volume_ratio(const dem::DemCell& cell) const;

  // The cell's P-wave modulus M = K + 4G/3 for the CFL condition, from its current coordination and
  // solid fraction (voigt_moduli with the full normal stiffness k_n of a bonded contact).
  double modulus(const dem::CellMeasures& m) const;
  // Seed Eq. 4 at velocity gradient L: the walls of the cell, moving at ḣ = L h, move by at most
  // Q_h d_min per MPM step. The walls are those of the seed's cell, the template deformed by F and
  // lattice-reduced: re-tiling and basis flips change how a packing is described, not how fast it
  // deforms, so they must not shrink the step (a doubled cell vector moves twice as fast).
  // A held cell with no contact and no bond (grains in free flight) has nothing whose deformation
  // the step must resolve, and sets no limit.
  double time_step_limit(const dem::DemCell& cell, const Mat2& L) const;
  // The same for a point that holds no cell, at in-plane deformation F since the template.
  double time_step_limit(const Mat2& F, const Mat2& L) const;

 private:
  // Eq. 4 for the template deformed by F (3D, since the template).
  double time_step_limit_of_deformed_template(const dem::Mat3& F, const Mat2& L) const;
  dem::DemCell with_cap(dem::DemCell cell) const {
    cell.set_retiling_cap(settings_.max_spheres);
    return cell;
  }

  dem::CellState template_state_;
  dem::Material material_;
  double skin_;
  LiveDemSettings settings_;
  double density_, mean_radius_, min_diameter_, template_volume_, template_volume_ratio_;
  dem::Mat3 template_deformation_inverse_;  // F of the template cell, inverted
};

}  // namespace grainbank::mpm
