// Gravity with an optional linear ramp: g(t) = g_from + (g_to - g_from) s(t) with
// s = clamp((t - t_start) / (t_end - t_start), 0, 1); without a ramp g(t) = g_to.
// (The reference implementation drops the g_from term; here g(t_start) = g_from exactly.)
#pragma once
#include <algorithm>
#include <optional>

#include "mpm_solver/core/types.hpp"

namespace grainbank::mpm {

struct GravityRamp {
  Vec2 from = Vec2::Zero();
  double start = 0, end = 0;  // [s], end > start
};

struct Gravity {
  Vec2 g = Vec2::Zero();  // final acceleration [m/s²]
  std::optional<GravityRamp> ramp;

  Vec2 at(double t) const {
    if (!ramp) return g;
    const double s = std::clamp((t - ramp->start) / (ramp->end - ramp->start), 0.0, 1.0);
    return ramp->from + (g - ramp->from) * s;
  }
};

}  // namespace grainbank::mpm
