#include "mpm_solver/io/coupling_report.hpp"

namespace grainbank::mpm::io {

StepCoupling step_coupling(const Solver& solver) {
  StepCoupling s;
  double error_sum = 0;
  for (const MaterialPoint& mp : solver.points()) {
    const DemBackedLaw* dem = solver.law(mp.law).dem_backed();
    switch (stress_source(solver.law(mp.law), mp.slot)) {
      case StressSource::analytic: ++s.analytic; break;
      case StressSource::live: ++s.live; break;
      case StressSource::hit: ++s.hits, error_sum += dem->estimated_error(mp.slot); break;
      case StressSource::miss: ++s.misses, error_sum += dem->estimated_error(mp.slot); break;
    }
  }
  if (s.hits + s.misses > 0) s.mean_estimated_error = error_sum / double(s.hits + s.misses);
  return s;
}

CouplingCounters coupling_counters(const Solver& solver, std::optional<std::size_t> law) {
  CouplingCounters total;
  for (const MaterialPoint& mp : solver.points())
    if (const DemBackedLaw* dem = solver.law(mp.law).dem_backed(); dem && (!law || mp.law == *law))
      total += dem->point_counters(mp.slot);
  return total;
}

nlohmann::json coupling_summary(const Solver& solver) {
  nlohmann::json laws = nlohmann::json::array();
  for (std::size_t k = 0; k < solver.law_count(); ++k) {
    const ConstitutiveLaw& law = solver.law(k);
    const CouplingCounters c = coupling_counters(solver, k);
    const std::uint64_t lookups = c.hits + c.misses;
    laws.push_back({{"law", law.name()},
                    {"hits", c.hits},
                    {"misses", c.misses},
                    {"hit_rate", c.hit_rate()},
                    {"mean_estimated_error", lookups ? c.estimated_error_sum / double(lookups) : 0.0},
                    {"live_point_steps", c.live_updates},
                    {"went_live", c.went_live},
                    {"returned_to_cache", c.returned_to_cache},
                    {"warm_start_increments", c.warm_start_increments},
                    {"warm_start_servo_steps", c.warm_start_servo_steps},
                    {"servo_unconverged", c.servo_unconverged},
                    {"warm_start_catch_up_steps", c.warm_start_catch_up_steps},
                    {"went_live_on_budget", c.went_live_on_budget},
                    {"reanchored", c.reanchored},
                    {"warm_start_seconds", c.warm_start_seconds},
                    {"enriched_paths", c.enriched_paths},
                    {"enriched_records", c.enriched_records},
                    {"retilings", c.retilings},
                    {"regenerations", c.regenerations},
                    {"regenerations_unconverged", c.regenerations_unconverged},
                    {"dispersed_holds", c.dispersed_holds}});
    for (const LawReport& report : {law.start_report(), law.end_report()})
      for (const auto& [path, value] : report.figures) laws.back()[nlohmann::json::json_pointer("/" + path)] = value;
  }
  return {{"laws", laws},
          {"skipped_point_steps", solver.skipped_updates()},
          {"point_steps", solver.point_updates()}};
}

}  // namespace grainbank::mpm::io
