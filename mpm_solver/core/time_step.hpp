// Critical time step of the explicit MPM: the MINIMUM of every stability criterion (the reference
// implementation takes the maximum, and has no wave-speed criterion for DEM points).
#pragma once
#include <algorithm>
#include <functional>
#include <limits>
#include <memory>
#include <vector>

#include "mpm_solver/core/constitutive_law.hpp"
#include "mpm_solver/core/grid.hpp"
#include "mpm_solver/core/material_point.hpp"
#include "mpm_solver/core/obstacle.hpp"

namespace grainbank::mpm {

struct TimeStepFactors {
  double cfl = 0.3;      // Δt ≤ cfl · h / max_p (c_p + |v_p|), c_p = sqrt(M_p / ρ_p)
  double contact = 0.2;  // Δt ≤ contact · sqrt(m_min / k_n,max) over active obstacles
};

struct TimeStepLimits {
  double wave = std::numeric_limits<double>::infinity();     // CFL
  double contact = std::numeric_limits<double>::infinity();  // obstacle springs
  double law = std::numeric_limits<double>::infinity();      // the laws' own limits (seed Eq. 4)
  double minimum() const { return std::min({wave, contact, law}); }
};

// Which points' own law limits count (a run spread over ranks asks each point's limit on the rank
// that holds its current state).
using PointFilter = std::function<bool(const MaterialPoint&)>;

// Uses each point's last velocity gradient for seed Eq. 4: the step is chosen before the new
// gradient is known, and never changed in the middle of a step.
TimeStepLimits critical_time_step(const Grid& grid, const std::vector<MaterialPoint>& points,
                                  const std::vector<std::unique_ptr<ConstitutiveLaw>>& laws,
                                  const std::vector<Obstacle>& obstacles, double time, const TimeStepFactors& factors,
                                  const PointFilter& law_limit_counts = {});

// The law's own limit of one point (seed Eq. 4 for DEM cells).
double law_limit_of(const MaterialPoint& mp, const std::vector<std::unique_ptr<ConstitutiveLaw>>& laws);

// Index of the point whose law limits the step most (the one behind TimeStepLimits::law) among those
// `counts` accepts, serially: for messages, not for every step. points.size() when none is accepted.
std::size_t law_limiting_point(const std::vector<MaterialPoint>& points,
                               const std::vector<std::unique_ptr<ConstitutiveLaw>>& laws,
                               const PointFilter& counts = {});

}  // namespace grainbank::mpm
