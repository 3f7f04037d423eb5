// A rigid obstacle (line or polygon) in frictional contact with material points seen as disks,
// through a DEM-like law (seed §2.1): f_n = max(0, k_n δ - c v_n) with c = 2 ζ sqrt(m k_n), and an
// incremental tangential spring f_t ← f_t - k_t v_t Δt capped by Coulomb, |f_t| ≤ μ f_n. Obstacles
// are fixed or move at a prescribed velocity, and may be removed at a given time (a gate) or let go
// of the body over an interval (ObstacleRelease).
//
// Where the force acts: at the point of the obstacle's surface that the disk touches, not at the
// disk's centre, for it is a traction on the body's boundary. Spread from the centre, half a point
// spacing inside the body, the cubic B-splines hand a floor's reaction to nodes up to two cells
// above it, and a column at rest carries its weight in the wrong rows: an elastic column of the
// cohesive study's size (0.3375 m on a 0.05625 m grid) at rest held 43 % and 32 % of the weight
// above its bottom row in that row, and 106 % and 116 % in the next, at one and two points per cell
// (stop 76). Acting at the surface, they hold 96 % and 98 % at one point per cell, 107 % and 86 % at
// two, and every point of the test column is within 2 % of ρ g H of its weight above
// (ElasticColumn.SelfWeightStressProfile).
#pragma once
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "mpm_solver/core/geometry.hpp"

namespace grainbank::mpm {

struct ContactParameters {
  double k_n = 0;            // normal stiffness [N/m per m of thickness] > 0
  double k_t = 0;            // tangential stiffness ≥ 0
  double friction = 0;       // Coulomb μ ≥ 0 (0: no tangential force at all)
  double damping_ratio = 0;  // ζ ∈ [0, 1] of the normal dashpot
};

// Largest overlap of a point's disk with an obstacle, as a fraction of the disk radius.
inline constexpr double kMaxPenetration = 0.5;

// A contact force and the point it acts at [N/m, m].
struct AppliedForce {
  Vec2 force = Vec2::Zero();
  Vec2 at = Vec2::Zero();
};

// When an obstacle lets go of the body: over [start, end] the normal force it gives each point is
// capped at s(t) f₀, where f₀ is the force that point had from it at `start` and
// s(t) = (end − t)/(end − start), and a disk pressed into it past kMaxPenetration of its radius is
// let through (no force) instead of refused. So the traction on the body's face falls linearly from
// what it carried to zero at `end`, however much the body leans on it; from `end` on it is gone. A
// sudden removal is start = end. Why: a gate removed at once sends an unloading wave through a
// column, which peaks at its corners and which a finer grid keeps sharper; let go over many wave
// transits, the face unloads quasi-statically.
struct ObstacleRelease {
  double start = std::numeric_limits<double>::infinity();  // [s]
  double end = std::numeric_limits<double>::infinity();    // [s] ≥ start
  static ObstacleRelease at(double t) { return {t, t}; }
  bool gradual() const { return end > start; }
};

struct PenetrationError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class Obstacle {
 public:
  // Throws std::invalid_argument on a bad shape or parameters.
  Obstacle(Polyline shape, ContactParameters contact, Vec2 velocity = Vec2::Zero(), ObstacleRelease release = {});

  bool active(double t) const { return t < release_.end; }
  const ObstacleRelease& release() const { return release_; }
  const ContactParameters& contact() const { return contact_; }
  const Vec2& velocity() const { return velocity_; }

  // Sizes the per-point histories for point ids [0, count): the tangential force (a frictionless
  // obstacle keeps none) and the normal force held at the release's start (a gradual release only).
  void reserve_points(std::size_t count) {
    if (contact_.friction > 0) tangential_.resize(count, 0.0);
    if (release_.gradual()) held_.resize(count, kNotHeldYet);
  }

  // Tangential contact forces, and normal forces at the release's start (NaN before it), by point id
  // (restart files).
  const std::vector<double>& tangential_history() const { return tangential_; }
  void set_tangential_history(std::vector<double> history) { tangential_ = std::move(history); }
  const std::vector<double>& held_forces() const { return held_; }
  void set_held_forces(std::vector<double> held) { held_ = std::move(held); }

  // Contact force on the disk (centre x, radius r, mass m) of point `id` at time t over a step dt, and
  // the surface point the disk touches; a zero force when apart. `velocity_at(touching)` gives the
  // material's velocity where the force acts (the solver's: material_velocity of the contact's
  // ContactSpread, transfers.hpp), asked only when the disk touches, the few points of a large body:
  // the dashpot and the friction then work against the motion of the material the force drives.
  // Updates only the history of `id` (safe across distinct points).
  // Throws PenetrationError when the disk overlaps the obstacle by more than kMaxPenetration of its
  // radius: the spring is too soft for the impact or for the load pressing the point in, and a centre
  // crossing a line would be pushed on through it (silent tunnelling) instead of back. The message says
  // which of the two it is: for an impact the k_n that would have stopped it, for a load the force the
  // spring holds at the allowed overlap. While the obstacle lets go (ObstacleRelease) such a disk is
  // let through instead.
  template <class VelocityAt>
  AppliedForce contact_force(std::uint32_t id, const Vec2& x, VelocityAt&& velocity_at, double radius, double mass,
                             double t, double dt) {
    const std::optional<Touch> touch = touching(x, radius, t);
    if (!touch) {
      if (contact_.friction > 0) tangential_[id] = 0;
      if (releasing(t)) held_at_start(id, 0);  // records that it was not held at the start
      return {Vec2::Zero(), x};
    }
    const Vec2 at = x - touch->normal * (radius - touch->overlap);
    return {force(id, *touch, velocity_at(at), radius, mass, t, dt), at};
  }

 private:
  struct Touch {
    Vec2 normal;     // unit, pushing the point out of the obstacle
    double overlap;  // > 0 [m]
  };
  std::optional<Touch> touching(const Vec2& x, double radius, double t) const;
  Vec2 force(std::uint32_t id, const Touch& touch, const Vec2& v, double radius, double mass, double t, double dt);
  bool releasing(double t) const { return release_.gradual() && t >= release_.start; }
  // The normal force point `id` had when the release started: `now` on its first call after the start.
  double held_at_start(std::uint32_t id, double now) {
    if (std::isnan(held_[id])) held_[id] = now;
    return held_[id];
  }
  static constexpr double kNotHeldYet = std::numeric_limits<double>::quiet_NaN();
  std::string penetration_message(double overlap, double radius, double mass, const Vec2& v) const;

  Polyline shape_;
  // The shape's bounding box: a disk farther from it than its radius cannot touch, and most points
  // of a body are, so they skip the exact test.
  Vec2 box_min_, box_max_;
  ContactParameters contact_;
  Vec2 velocity_;
  ObstacleRelease release_;
  std::vector<double> tangential_;  // f_t along the contact tangent, per point id
  std::vector<double> held_;        // f₀ of ObstacleRelease, per point id
};

}  // namespace grainbank::mpm
