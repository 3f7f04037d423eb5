#include "mpm_solver/core/obstacle.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace grainbank::mpm {

Obstacle::Obstacle(Polyline shape, ContactParameters contact, Vec2 velocity, ObstacleRelease release)
    : shape_(std::move(shape)), contact_(contact), velocity_(velocity), release_(release) {
  check(shape_);
  box_min_ = box_max_ = shape_.vertices.front();
  for (const Vec2& v : shape_.vertices) {
    box_min_ = box_min_.cwiseMin(v);
    box_max_ = box_max_.cwiseMax(v);
  }
  if (!(contact_.k_n > 0) || !std::isfinite(contact_.k_n)) throw std::invalid_argument("k_n: expected a positive number");
  if (!(contact_.k_t >= 0) || !std::isfinite(contact_.k_t)) throw std::invalid_argument("k_t: expected a number >= 0");
  if (!(contact_.friction >= 0) || !std::isfinite(contact_.friction))
    throw std::invalid_argument("friction: expected a number >= 0");
  if (!(contact_.damping_ratio >= 0 && contact_.damping_ratio <= 1))
    throw std::invalid_argument("damping: expected a number in [0, 1]");
  if (!velocity_.allFinite()) throw std::invalid_argument("velocity: expected finite numbers");
  if (!(release_.start >= 0) || !(release_.end >= release_.start))
    throw std::invalid_argument("release: expected 0 <= start <= end");
}

std::string Obstacle::penetration_message(double overlap, double radius, double mass, const Vec2& v) const {
  const double speed = (v - velocity_).norm();
  // A point arriving at `speed` is stopped within kMaxPenetration·radius by a spring storing its kinetic
  // energy: ½ k_n (kMaxPenetration r)² ≥ ½ m v².
  const double allowed = kMaxPenetration * radius;
  const double impact_k_n = mass * speed * speed / (allowed * allowed);
  std::ostringstream msg;
  msg << "penetrates the obstacle by " << overlap << " m, more than " << kMaxPenetration << " of its disk radius "
      << radius << " m, at speed " << speed << " m/s: raise the obstacle's k_n (now " << contact_.k_n << " N/m per m)";
  if (contact_.k_n < impact_k_n) {
    msg << " above " << impact_k_n << ", what stops a point at this speed within " << allowed
        << " m (k_n > m v^2 / (" << kMaxPenetration << " radius)^2), or lower the impact speed";
  } else {
    // Its speed alone would have been stopped: the load on it (the stress of the material above,
    // gravity) presses it in, past what the spring holds at the allowed overlap.
    msg << ": the load pressing it in (the stress of the material above it, gravity) exceeds the "
        << contact_.k_n * allowed << " N/m it holds within " << allowed
        << " m, while its speed alone needs only k_n > m v^2 / (" << kMaxPenetration << " radius)^2 = " << impact_k_n
        << "; check the stress its law returns too";
  }
  return msg.str();
}

std::optional<Obstacle::Touch> Obstacle::touching(const Vec2& x, double radius, double t) const {
  // Work in the obstacle's frame: it only translates.
  const Vec2 x_local = x - velocity_ * t;
  // Outside the box by more than the radius (with a margin for the rounding of the distance below):
  // not inside, and farther than the radius from every edge.
  const double reach = radius * (1 + 1e-9);
  if ((x_local.array() < box_min_.array() - reach).any() || (x_local.array() > box_max_.array() + reach).any())
    return std::nullopt;
  const Vec2 to_point = x_local - closest_point(shape_, x_local);
  const double d = to_point.norm();
  const bool inside = contains(shape_, x_local);
  const double overlap = inside ? radius + d : radius - d;
  if (overlap <= 0 || d == 0) return std::nullopt;
  return Touch{(inside ? -to_point : to_point) / d, overlap};
}

Vec2 Obstacle::force(std::uint32_t id, const Touch& touch, const Vec2& v, double radius, double mass, double t,
                     double dt) {
  // Held or let go of (ObstacleRelease): the spring and dashpot stay as they are, and a release caps
  // their normal force at the share s(t) of what the point had at its start.
  const bool letting_go = releasing(t);
  if (touch.overlap > kMaxPenetration * radius) {
    if (!letting_go) throw PenetrationError(penetration_message(touch.overlap, radius, mass, v));
    if (contact_.friction > 0) tangential_[id] = 0;
    held_at_start(id, 0);
    return Vec2::Zero();
  }
  const Vec2& n = touch.normal;
  const Vec2 v_rel = v - velocity_;
  const double damping = 2 * contact_.damping_ratio * std::sqrt(mass * contact_.k_n);
  double fn = std::max(0.0, contact_.k_n * touch.overlap - damping * v_rel.dot(n));
  if (letting_go) fn = std::min(fn, held_at_start(id, fn) * (release_.end - t) / (release_.end - release_.start));
  if (contact_.friction == 0) return fn * n;
  const Vec2 tangent(-n.y(), n.x());
  const double cap = contact_.friction * fn;
  double& ft = tangential_[id];
  ft = std::clamp(ft - contact_.k_t * v_rel.dot(tangent) * dt, -cap, cap);
  return fn * n + ft * tangent;
}

}  // namespace grainbank::mpm
