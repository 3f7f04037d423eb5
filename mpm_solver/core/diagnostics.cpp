#include "mpm_solver/core/diagnostics.hpp"

#include <algorithm>
#include <limits>

namespace grainbank::mpm {

FlowMeasures measure_flow(const std::vector<MaterialPoint>& points) {
  FlowMeasures m;
  if (points.empty()) return m;
  m.front = m.max_height = -std::numeric_limits<double>::infinity();
  for (const MaterialPoint& mp : points) {
    m.kinetic_energy += 0.5 * mp.mass * mp.velocity.squaredNorm();
    m.momentum += mp.mass * mp.velocity;
    m.front = std::max(m.front, mp.position.x());
    m.max_height = std::max(m.max_height, mp.position.y());
    m.max_speed = std::max(m.max_speed, mp.velocity.norm());
  }
  return m;
}

}  // namespace grainbank::mpm
