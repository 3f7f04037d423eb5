// A tri-periodic cell of bonded frictional spheres driven by its cell matrix: the micro scale of the
// seed's MPM×DEM method. Owns its particles and interaction history; knows no file format.
//
// Kinematics: x = h s. Velocities split into the affine part L x (L = ḣ h⁻¹) and the fluctuation v';
// when L changes the fluctuation is kept, i.e. the affine change applies to every sphere at once.
// Spins split the same way, ω = w + ω' with w the cell's spin (W x = w × x, W = skew L): a change of
// L spins every grain up by the change of w at once, so a cell switched to a rigid rotation turns its
// grains with it instead of making its contacts slip by w × ℓ until friction has spun them up.
// Fluctuations obey m dv'/dt = f - m Lᵀ v' = f - m (D - W) v': the stretching D exchanges exactly
// V σ_kinetic : D with the fluctuations (as SLLOD), while the spin W only turns them with the cell, so
// a rigidly rotated cell behaves as the unrotated one (objectivity; SLLOD's -W v' is a Coriolis term).
// The macroscopic acceleration of the affine field is the MPM's business, not the cell's.
// Velocity Verlet for translations and rotations.
//
// Stress is tension-positive (MPM convention): σ = -(1/V) (Σ_pairs f ⊗ ℓ + Σ_spheres m v'⊗v'),
// the second term only when the kinetic-stress effect is on (seed Eq. 2).
#pragma once
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "dem_sampler/cell/cell_state.hpp"
#include "dem_sampler/cell/interaction_law.hpp"
#include "dem_sampler/cell/material.hpp"
#include "dem_sampler/cell/pair_table.hpp"
#include "dem_sampler/cell/periodic_cell.hpp"
#include "dem_sampler/cell/substepping.hpp"
#include "dem_sampler/cell/verlet_list.hpp"

namespace grainbank::dem {

struct CellMeasures {
  double time = 0;
  Mat3 stress = Mat3::Zero();        // tension-positive [Pa], at the last measured step
  double solid_fraction = 0;         // φ
  double coordination = 0;           // Z = 2 × (pairs carrying force) / N
  std::int64_t bonds = 0;            // N_b
  double damage = 0;                 // D = 1 - N_b / N_b(0) (seed Eq. 6); 0 without bonds
  double kinetic_energy = 0;         // of the fluctuations, translational + rotational [J]
  double unbalanced_force_ratio = 0; // mean |net force on a sphere| / mean |pair force|
};

// Result of driving the cell through one macroscopic increment.
struct IncrementResult {
  Mat3 stress = Mat3::Zero();  // regressed over the last Q_σ of the increment, at its end
  long substeps = 0;
  double substep = 0;          // δt actually used: Δt / substeps
};

// Mixed control for preparation and stand-alone tests: each component of the velocity gradient is
// either prescribed, or servo-controlled so that the same stress component reaches its target.
struct MixedControl {
  Mat3 velocity_gradient = Mat3::Zero();               // prescribed components of L [1/s]
  Eigen::Matrix<bool, 3, 3> stress_controlled = Eigen::Matrix<bool, 3, 3>::Constant(false);
  Mat3 target_stress = Mat3::Zero();                   // tension-positive targets [Pa]
  double stress_scale = 1;   // stress error that drives the cell at max_rate [Pa]
  double max_rate = 0;       // largest servo strain rate [1/s]
};

class DemCell {
 public:
  // Takes a complete state (see cell_state.hpp). Throws std::invalid_argument on inconsistent sizes
  // or parameters. `skin` is the Verlet skin [m].
  DemCell(CellState state, Material material, double skin);

  // Builds a fresh cell: spheres at rest, no history; the Verlet list is built and forces computed.
  static DemCell from_packing(const Mat3& h, const std::vector<Vec3>& positions, const std::vector<double>& radii,
                              const Material& material, double skin);

  // Seed Eq. 3 for this cell's lightest sphere, over its stiffest mode (see dem_time_step).
  double time_step(double q_t) const;

  // Drives h from its current value h0 to F_inc h0 over `duration` at the constant velocity gradient
  // log(F_inc)/Δt, in n = max(ceil(Δt/δt), Q_n) steps of exactly Δt/n, and returns the stress
  // regressed over the last Q_σ of the increment. F_inc needs det > 0 and no rotation by π.
  IncrementResult advance(const Mat3& increment, double duration, const Substepping& q);

  // One step with a constant velocity gradient L (ḣ = L h, explicit).
  void step_with_velocity_gradient(const Mat3& L, double dt);

  // One step under mixed control; the stress is measured at every such step.
  void step_mixed(const MixedControl& control, double dt);

  // Bonds every pair whose gap is below ε (R_i + R_j), stress-free at creation; sets N_b(0).
  // Requires the bonds effect. Returns the number of bonds.
  std::int64_t create_bonds(double bonding_distance);

  // Cundall local damping α ∈ [0,1) for quasi-static relaxation (preparation only; 0 = off).
  void set_local_damping(double alpha) { local_damping_ = alpha; }
  // Replaces the friction coefficient (preparation lowers it to control density).
  void set_friction(double mu);

  // Re-tiling (retiling.hpp): before a step, a cell whose smallest width after lattice reduction is
  // within kRetileMargin of twice the interaction range is replaced by its supercell doubled along
  // that width, as long as it then holds at most `max_spheres` spheres; beyond that the cell goes on
  // until it is too thin and throws CellTooThinError, as without re-tiling. 0 (the default): off.
  void set_retiling_cap(std::size_t max_spheres) { retiling_cap_ = max_spheres; }
  static constexpr double kRetileMargin = 1.1;
  // True when re-tiling is on and the cell is due to re-tile but doubling would pass the cap: the
  // caller may replace it (cell/regeneration.hpp) before it becomes too thin.
  bool thin_beyond_retiling_cap() const;

  CellMeasures measures() const;
  // The stress at the last measured step (measures().stress without the other sums).
  const Mat3& stress() const { return stress_; }
  const Mat3& cell_matrix() const { return h_; }
  Mat3 deformation_gradient() const { return h_ * h_ref_.inverse(); }
  double volume() const { return cell_volume(h_); }
  double time() const { return time_; }
  std::size_t size() const { return radius_.size(); }
  std::size_t pair_count() const { return pairs_.size(); }
  std::size_t contact_count() const;           // pairs with overlap
  // Pairs in contact or bonded at the last measured step: 0 for a cell whose spheres fly free.
  std::int64_t interacting_pairs() const { return active_pairs_; }
  std::int64_t initial_bond_count() const { return initial_bonds_; }  // N_b(0) of seed Eq. 6
  double max_overlap() const;                  // largest -d_n / (R_i + R_j) over the pairs (0: none)
  std::int64_t flips() const { return flips_; }
  std::int64_t list_builds() const { return list_builds_; }
  const Material& material() const { return material_; }
  double skin() const { return skin_; }
  // Real positions x = h s (s as stored, not wrapped).
  std::vector<Vec3> positions() const;
  const std::vector<double>& radii() const { return radius_; }
  const std::vector<Vec3>& velocities() const { return u_; }
  // Bytes held by the cell's arrays (for memory reports).
  std::size_t memory_bytes() const;

  CellState state() const;

 private:
  // The bond law the force loop is compiled for: the yield surface's exponent p (2 needs no power)
  // and whether the bond softens past it (interaction_law.hpp).
  enum class BondForm : std::size_t { kBrittlePower, kBrittleQuadratic, kSofteningQuadratic };
  static constexpr std::size_t kBondForms = 3;
  template <bool Bonds, bool Rolling, bool Measure, BondForm Form>
  void compute_forces(double dt);
  void compute_forces(bool measure, double dt);
  template <std::size_t... Flags>
  static constexpr auto force_kernels(std::index_sequence<Flags...>);
  // Moves to h_new over dt (constant ḣ); measures stress when asked. Throws diverged(...) when the
  // cell or a sphere is no longer finite.
  void step_to(const Mat3& h_new, double dt, bool measure);
  // "DEM cell diverged at t = …: WHAT; …" with what to change.
  std::runtime_error diverged(const std::string& what) const;
  void update_positions();
  void update_shifts();
  // max_displacement2: largest squared fluctuation displacement since the last rebuild.
  bool list_is_stale(double max_displacement2) const;
  void rebuild_list();
  // Branch vector ℓ of Verlet pair k, from i to the listed image of j, at the current positions.
  Vec3 branch(std::size_t k) const { return x_[pairs_.j[k]] - x_[pairs_.i[k]] + shift_[pairs_.image[k]]; }
  // Shift code of the periodic image of j nearest to i.
  int closest_image(std::uint32_t i, std::uint32_t j) const;
  // Flips to a reduced basis if due; returns M (identity if nothing changed).
  IntMat3 reduce_if_needed();
  // Re-tiles if due (see set_retiling_cap); returns M (identity if nothing changed).
  Mat3 retile_if_needed();
  // The smallest width is within kRetileMargin of twice the interaction range.
  bool due_to_retile() const;
  // Velocity Verlet halves (dem_cell_motion.cpp): first kick + drift (returns the largest squared
  // fluctuation displacement since the last list build), and the closing kick. Damped = Cundall
  // local damping on.
  template <bool Damped>
  double kick_and_drift(double dt, const Mat3& L, const Mat3& h_mid_inv, const Mat3& h_new);
  template <bool Damped>
  void kick(double half_dt, const Mat3& L);

  Material material_;
  InteractionCoefficients coef_;
  double skin_;
  double max_radius_ = 0, min_mass_ = 0, min_radius_ = 0;
  double local_damping_ = 0;
  std::size_t retiling_cap_ = 0;

  Mat3 h_, h_inv_, h_ref_, L_ = Mat3::Zero();
  double time_ = 0;
  std::vector<double> radius_, mass_, inv_mass_, inv_inertia_;
  std::vector<Vec3> s_, u_, omega_, x_, force_, torque_;
  PairTable pairs_;                     // with bonds and rolling moments when those effects are on
  std::int64_t initial_bonds_ = 0;
  Vec3 shift_[kShiftCount];             // h n for every image code

  Mat3 h_build_;
  std::vector<Vec3> s_build_;
  VerletListBuilder builder_;
  std::vector<Pair> scratch_pairs_;     // the builder's output, kept to reuse its memory
  std::int64_t flips_ = 0, list_builds_ = 0;

  // Accumulated by a measuring force evaluation.
  Mat3 stress_ = Mat3::Zero();
  double sum_pair_force_ = 0;
  std::int64_t active_pairs_ = 0;
};

}  // namespace grainbank::dem
