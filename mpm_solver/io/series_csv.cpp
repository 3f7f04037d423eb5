#include "mpm_solver/io/series_csv.hpp"

#include <algorithm>
#include <stdexcept>

#include "mpm_solver/core/diagnostics.hpp"
#include "mpm_solver/io/coupling_report.hpp"

namespace grainbank::mpm::io {

namespace {
std::ofstream open_csv(const std::filesystem::path& file, const char* header) {
  std::ofstream out(file);
  if (!out) throw std::runtime_error(file.string() + ": cannot open for writing");
  out.precision(17);
  out << header << '\n';
  return out;
}
}  // namespace

SeriesCsv::SeriesCsv(const std::filesystem::path& file)
    : out_(open_csv(file, "t,dt,step,kinetic_energy,front,max_height,max_velocity,limit_wave,limit_contact,limit_law,"
                        "hits,misses,live_cells,hit_rate,mean_estimated_error,went_live,warm_start_time,skipped_point_steps,"
                        "retilings,regenerations")) {}

FlowMeasures SeriesCsv::write(const Solver& solver, double last_dt, const TimeStepLimits& limits) {
  const FlowMeasures m = measure_flow(solver.points());
  out_ << solver.time() << ',' << last_dt << ',' << solver.steps() << ',' << m.kinetic_energy << ',' << m.front << ','
       << m.max_height << ',' << m.max_speed << ',' << limits.wave << ',' << limits.contact << ',' << limits.law;
  const StepCoupling c = step_coupling(solver);
  const CouplingCounters total = coupling_counters(solver);
  out_ << ',' << c.hits << ',' << c.misses << ',' << c.live << ',' << c.hit_rate() << ',' << c.mean_estimated_error << ','
       << total.went_live << ',' << total.warm_start_seconds << ',' << solver.skipped_updates() << ','
       << total.retilings << ',' << total.regenerations << '\n';
  out_.flush();  // rows reach the disk as they come: a long run can be watched, and a killed one keeps them
  return m;
}

TrackedCsv::TrackedCsv(const std::filesystem::path& file, std::vector<std::uint32_t> ids)
    : out_(open_csv(file, "t,point,x,y,vx,vy,sxx,syy,sxy,szz,p,q,strain_rate_q,damage,density")), ids_(std::move(ids)) {}

void TrackedCsv::write(const Solver& solver) {
  for (std::uint32_t id : ids_) {
    const auto& pts = solver.points();
    const auto it = std::find_if(pts.begin(), pts.end(), [id](const MaterialPoint& mp) { return mp.id == id; });
    const MaterialPoint& mp = *it;
    const Mat2& s = mp.stress.in_plane;
    out_ << solver.time() << ',' << id << ',' << mp.position.x() << ',' << mp.position.y() << ',' << mp.velocity.x()
         << ',' << mp.velocity.y() << ',' << s(0, 0) << ',' << s(1, 1) << ',' << s(0, 1) << ',' << mp.stress.zz << ','
         << pressure_of(mp.stress) << ',' << deviatoric_stress_of(mp.stress) << ','
         << deviatoric_strain_rate(mp.velocity_gradient) << ',' << solver.law(mp.law).damage(mp.slot) << ','
         << mp.mass / mp.volume << '\n';
  }
  out_.flush();
}

}  // namespace grainbank::mpm::io
