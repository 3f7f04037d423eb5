// The 2D plane-strain MPM solver: material points on a regular grid with cubic B-splines, explicit
// MUSL time integration with APIC (or the FLIP/PIC blend), gravity and rigid obstacles. Knows no file format:
// scenes are built through this interface (io/ reads them from JSON).
#pragma once
#include <optional>
#include <memory>
#include <vector>

#include "mpm_solver/core/channel_walls.hpp"
#include "mpm_solver/core/constitutive_law.hpp"
#include "mpm_solver/core/gravity.hpp"
#include "mpm_solver/core/grid.hpp"
#include "mpm_solver/core/homogeneous_drive.hpp"
#include "mpm_solver/core/material_point.hpp"
#include "mpm_solver/core/nonlocal_average.hpp"
#include "mpm_solver/core/obstacle.hpp"
#include "mpm_solver/core/point_distribution.hpp"
#include "mpm_solver/core/time_step.hpp"
#include "mpm_solver/core/transfers.hpp"

namespace grainbank::mpm {

struct SolverSettings {
  VelocityTransfer transfer;
  TimeStepFactors time_step;
  double max_time_step = std::numeric_limits<double>::infinity();
  int sort_interval = 20;         // re-sort points by cell every this many steps (memory locality)
  // A point whose motion since its last constitutive call (the increments of the steps it skipped
  // composed, stretch and rotation: |F_pending - I|) stays below this skips the call, and so does
  // its stress, which lags the motion by at most this relative amount. The law later receives the
  // whole pending motion with the time it took. 0 = never skip.
  double skip_strain_increment = 0;
  // On several ranks, the live cells are re-dealt by their measured cost every this many steps
  // (PointDistribution::rebalance).
  int rebalance_interval = 50;
  // When set, the whole domain is driven homogeneously (element tests); forces are then ignored.
  std::optional<HomogeneousDrive> homogeneous_drive;
  // When set, each point's law is driven by the velocity gradient averaged over this length
  // (nonlocal_average.hpp): the regularization of softening materials.
  std::optional<NonlocalAverage> regularization;
  // When set, the flow runs between two side walls parallel to its plane that take friction
  // (channel_walls.hpp).
  std::optional<ChannelWalls> channel_walls;
};

// Wall time spent in each part of the step [s], summed over steps.
struct PhaseTimes {
  double contact = 0, particles_to_grid = 0, grid = 0, grid_to_particles = 0, stress = 0, sort = 0;
};

class Solver {
 public:
  Solver(Grid grid, SolverSettings settings);

  // Laws first, then points that refer to them by index; obstacles and gravity at any time.
  std::size_t add_law(std::unique_ptr<ConstitutiveLaw> law);
  // A point of `volume` [m²] with the law's density; throws std::invalid_argument outside the grid.
  std::uint32_t add_point(std::size_t law, const Vec2& position, double volume, double radius,
                          const Vec2& velocity = Vec2::Zero());
  void add_obstacle(Obstacle obstacle);
  void set_gravity(const Gravity& gravity) { gravity_ = gravity; }
  // Drives the whole domain homogeneously from the next step on (see homogeneous_drive.hpp).
  void set_homogeneous_drive(std::optional<HomogeneousDrive> drive) { settings_.homogeneous_drive = drive; }

  // Spreads the run over `ranks` (MPI): call after the laws are added, before the first step, on every
  // rank alike. Throws std::invalid_argument when a law cannot run on several ranks. From then on
  // step(), time_step_limits(), law_limiting_point() and gather_point_states() are collective calls.
  void set_ranks(std::shared_ptr<const Ranks> ranks);
  const Ranks& ranks() const { return distribution_.ranks(); }
  // Brings the law state of the points in `ids` (all when empty) to rank 0, before it reads a
  // spread point's full state (a restart file, a tracked point's cell).
  void gather_point_states(const std::vector<std::uint32_t>& ids = {});

  // Criteria for the next step (their minimum, capped by max_time_step, is the step to take).
  TimeStepLimits time_step_limits() const;
  double stable_time_step() const;
  // The point whose law sets TimeStepLimits::law (law_limiting_point); requires a point.
  const MaterialPoint& law_limiting_point() const;

  // One MUSL step of length dt. Throws std::runtime_error (naming the point) when a point leaves
  // the grid, penetrates an obstacle too deeply (naming the obstacle) or its law fails; the solver
  // is then not to be stepped further.
  void step(double dt);
  // Ends the run: every law writes what it still holds (ConstitutiveLaw::finish). Call once, after
  // the last step.
  void finish();

  double time() const { return time_; }
  long steps() const { return steps_; }
  const Grid& grid() const { return grid_; }
  const std::vector<MaterialPoint>& points() const { return points_; }
  const ConstitutiveLaw& law(std::size_t index) const { return *laws_[index]; }
  std::size_t law_count() const { return laws_.size(); }
  const std::vector<Obstacle>& obstacles() const { return obstacles_; }
  const Gravity& gravity() const { return gravity_; }
  const SolverSettings& settings() const { return settings_; }
  const PhaseTimes& phase_times() const { return phase_times_; }
  // Point-steps that skipped the constitutive call (skip_strain_increment), and all point-steps.
  long skipped_updates() const { return skipped_updates_; }
  long point_updates() const { return point_updates_; }
  // Wall time spent on each point's law state on this rank so far [s] (its constitutive calls and its
  // own time-step limit), by point id, for the points of laws spread over ranks (PointSharing: the
  // costly ones); 0 for the others.
  const std::vector<double>& point_update_seconds() const { return point_update_seconds_; }
  // Bytes the ranks exchanged after the stress updates so far (0 on one rank).
  double shared_update_bytes() const { return distribution_.shared_update_bytes(); }
  // Points whose law state moved to another rank to balance the load so far (0 on one rank).
  std::size_t rebalanced_points() const { return distribution_.moved_points(); }

  // Restart support: mutable access to the laws and obstacles (whose states a restart file
  // restores), and replacement of the time, step count and points of a solver built from the same
  // scene.
  ConstitutiveLaw& law(std::size_t index) { return *laws_[index]; }
  Obstacle& obstacle(std::size_t index) { return obstacles_[index]; }
  void restore(double time, long steps, std::vector<MaterialPoint> points);
  // The integral of the homogeneous drive's normal-stress servo [1/s] (homogeneous_drive.hpp).
  double drive_integral() const { return drive_integral_; }
  void restore_drive_integral(double integral) { drive_integral_ = integral; }

 private:
  void sort_points_by_cell();
  void rebalance();  // re-deals the spread points by their cost since the last call
  void locate_points();           // stencils; throws if a point left the grid
  void apply_obstacle_contacts(double dt);
  void update_stresses(double dt);

  Grid grid_;
  SolverSettings settings_;
  std::vector<std::unique_ptr<ConstitutiveLaw>> laws_;
  std::vector<MaterialPoint> points_;
  struct TouchingContact {
    Vec2 force;
    ContactSpread spread;
  };
  std::vector<std::vector<TouchingContact>> touching_;  // this step's contacts, per OpenMP thread
  std::vector<Stencil> stencils_;
  std::vector<Vec2> fluctuations_;  // G2P's d_p, when the transfer blends its rough part apart
  std::vector<Obstacle> obstacles_;
  Gravity gravity_;
  ScatterBuffers buffers_;
  PointDistribution distribution_;
  double time_ = 0;
  long steps_ = 0;
  long skipped_updates_ = 0, point_updates_ = 0;
  double drive_integral_ = 0;
  mutable std::vector<double> point_update_seconds_;  // time_step_limits() adds to it
  std::vector<double> point_update_seconds_at_rebalance_;
  PhaseTimes phase_times_;
};

}  // namespace grainbank::mpm
