// The one interface behind which every constitutive law of the MPM sits. A law owns the state of all
// its points, addressed by slot; distinct slots may be updated concurrently, so update() must only
// touch its own slot. Laws register themselves by name (laws/law_registry.hpp); the solver knows them
// only through this interface.
#pragma once
#include <cstddef>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "mpm_solver/core/kinematic_increment.hpp"
#include "mpm_solver/core/law_state_archive.hpp"
#include "mpm_solver/core/types.hpp"

namespace grainbank::mpm {

class DemBackedLaw;
class PointSharing;

// What a law settled on when it was built, or measured of its run at the end: figures by path (e.g.
// "length_scales/phi/scale"; the run's summary nests them at each '/'), and notes its user should
// read before trusting the run.
struct LawReport {
  std::vector<std::pair<std::string, double>> figures;
  std::vector<std::string> notes;
};

class ConstitutiveLaw {
 public:
  virtual ~ConstitutiveLaw() = default;

  // The name the law is registered under ("elastic", "drucker_prager", "live", "cache", "hybrid").
  virtual std::string name() const = 0;
  // Density of new points [kg/m³] (for a DEM-backed law: of its cell, spheres and voids).
  virtual double density() const = 0;
  // Creates the state of one more point and returns its slot and initial stress.
  virtual std::size_t add_point(PointStress& initial_stress) = 0;

  // Drives point `slot` through `increment`, the in-plane motion since the law's last call of this
  // slot (plane strain: ε_zz = 0), after which the point's deformation gradient is F; replaces
  // `stress` by the new Cauchy stress (tension-positive). The increment may span several MPM steps
  // (SolverSettings::skip_increment): its dt is all the time they took.
  virtual void update(std::size_t slot, const KinematicIncrement& increment, const Mat2& F, PointStress& stress) = 0;

  // Current volume over initial volume of the point, given `kinematic`, the ratio its motion gives:
  // the product of its steps' det F_inc = e^{tr L dt}. That is det F in exact arithmetic, but stays
  // positive and exact where det F of a point sheared without bound is lost to round-off. A law whose
  // material has a volume of its own (a DEM cell's) returns that.
  virtual double volume_ratio(std::size_t /*slot*/, double kinematic) const { return kinematic; }
  // P-wave modulus M = K + 4G/3 [Pa] for the CFL condition, c = sqrt(M / ρ).
  virtual double p_wave_modulus(std::size_t slot) const = 0;
  // Largest MPM time step the law itself allows for a point of deformation gradient F at velocity
  // gradient L (seed Eq. 4 for DEM cells).
  virtual double time_step_limit(std::size_t /*slot*/, const Mat2& /*F*/, const Mat2& /*L*/) const {
    return std::numeric_limits<double>::infinity();
  }
  // Seed Eq. 6 damage D of the point (0 for laws without bonds).
  virtual double damage(std::size_t /*slot*/) const { return 0; }
  // True when an update costs far more than a few flops (the solver then schedules dynamically).
  // Asked every step: a law may become expensive (a hybrid law once some of its points are live).
  virtual bool expensive() const { return false; }

  // What the law's points carry from step to step besides the point's own kinematics and stress
  // (restart files): saved after any step and restored into a law built from the same scene with the
  // same points, the run continues as if uninterrupted. Laws whose points carry nothing else keep
  // the defaults.
  virtual void save_state(LawStateWriter& /*out*/) const {}
  virtual void restore_state(LawStateReader& /*in*/) {}

  // Ends a step: called once after every point of the step was updated, outside any parallel region.
  // A law whose points learn from each other publishes here what they learned in the step, in slot
  // order, so that no point's update depends on which other points a thread reached first: the run
  // is the same on any number of threads.
  virtual void end_step() {}

  // Ends the run (Solver::finish): writes what the law still holds (e.g. live responses for the
  // library). Called once, after the last step; throws with context when that fails.
  virtual void finish() {}

  // A run spread over several ranks (core/ranks.hpp) replicates a law whose update of a point
  // depends on nothing but the point and that writes nothing (replicable: every rank updates every
  // point alike), and spreads the points of a law with a PointSharing over the ranks. A law with
  // neither runs on one rank only.
  virtual bool replicable() const { return false; }
  virtual PointSharing* point_sharing() { return nullptr; }

  // For the run's summary and its start (mpm_solver prints the notes); most laws settle on nothing.
  virtual LawReport start_report() const { return {}; }
  // For the run's summary and its end, after finish() (mpm_solver prints the notes); most laws
  // measure nothing of their run.
  virtual LawReport end_report() const { return {}; }

  // The DEM-backed side of the law (live cells, library answers), or null for an analytic law.
  virtual const DemBackedLaw* dem_backed() const { return nullptr; }
};

}  // namespace grainbank::mpm
