#include "mpm_solver/core/time_step.hpp"

#include <cmath>

#include "mpm_solver/core/parallel.hpp"

namespace grainbank::mpm {

double law_limit_of(const MaterialPoint& mp, const std::vector<std::unique_ptr<ConstitutiveLaw>>& laws) {
  return laws[mp.law]->time_step_limit(mp.slot, mp.deformation_gradient, mp.velocity_gradient);
}

TimeStepLimits critical_time_step(const Grid& grid, const std::vector<MaterialPoint>& points,
                                  const std::vector<std::unique_ptr<ConstitutiveLaw>>& laws,
                                  const std::vector<Obstacle>& obstacles, double time, const TimeStepFactors& factors,
                                  const PointFilter& law_limit_counts) {
  double max_signal = 0, min_mass = std::numeric_limits<double>::infinity();
  double law_limit = std::numeric_limits<double>::infinity();
  const long n = static_cast<long>(points.size());
#pragma omp parallel for schedule(static) reduction(max : max_signal) reduction(min : min_mass, law_limit) \
    if (n >= kMinParallelItems)
  for (long p = 0; p < n; ++p) {
    const MaterialPoint& mp = points[p];
    const ConstitutiveLaw& law = *laws[mp.law];
    const double density = mp.mass / mp.volume;
    max_signal = std::max(max_signal, std::sqrt(law.p_wave_modulus(mp.slot) / density) + mp.velocity.norm());
    min_mass = std::min(min_mass, mp.mass);
    if (!law_limit_counts || law_limit_counts(mp)) law_limit = std::min(law_limit, law_limit_of(mp, laws));
  }
  TimeStepLimits limits;
  if (max_signal > 0) limits.wave = factors.cfl * grid.cell_size() / max_signal;
  limits.law = law_limit;
  double k_max = 0;
  for (const Obstacle& o : obstacles)
    if (o.active(time)) k_max = std::max({k_max, o.contact().k_n, o.contact().k_t});
  if (k_max > 0 && n > 0) limits.contact = factors.contact * std::sqrt(min_mass / k_max);
  return limits;
}

std::size_t law_limiting_point(const std::vector<MaterialPoint>& points,
                               const std::vector<std::unique_ptr<ConstitutiveLaw>>& laws, const PointFilter& counts) {
  std::size_t worst = points.size();
  double worst_limit = std::numeric_limits<double>::infinity();
  for (std::size_t p = 0; p < points.size(); ++p) {
    if (counts && !counts(points[p])) continue;
    const double limit = law_limit_of(points[p], laws);
    if (worst == points.size() || limit < worst_limit) worst = p, worst_limit = limit;
  }
  return worst;
}

}  // namespace grainbank::mpm
