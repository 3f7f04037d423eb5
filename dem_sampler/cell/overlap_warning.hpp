// Large overlaps. The linear contact law (interaction_law.hpp) stays stable at any overlap: its
// contact period, hence the step of seed Eq. 3, does not depend on it. But grains overlapping by
// more than a few per cent of their radius sum interpenetrate unphysically: k_n is too soft for the
// pressure. The engine does not print; callers (CLI, sampler, MPM) show this text to the user.
#pragma once
#include <optional>
#include <sstream>
#include <string>

#include "dem_sampler/cell/dem_cell.hpp"

namespace grainbank::dem {

// Overlap ratio -d_n / (R_i + R_j) above which a cell is reported.
inline constexpr double kLargeOverlap = 0.05;

// A one-line warning naming the largest overlap, the limit and the remedy, or nothing.
inline std::optional<std::string> large_overlap_warning(const DemCell& cell, double limit = kLargeOverlap) {
  const double overlap = cell.max_overlap();
  if (!(overlap > limit)) return std::nullopt;
  std::ostringstream msg;
  msg << "large overlaps: the largest is " << 100 * overlap << "% of the pair's radius sum (limit " << 100 * limit
      << "%) at pressure " << -cell.measures().stress.trace() / 3
      << " Pa; the contact law is linear, so results stay finite, but raise contact.k_n or lower the pressure";
  return msg.str();
}

}  // namespace grainbank::dem
