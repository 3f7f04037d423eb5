#include "mpm_solver/app/audit_command.hpp"

#include <algorithm>
#include <fstream>
#include <iomanip>
#include <set>
#include <string>

#include "database/audit/audit_report.hpp"
#include "mpm_solver/audit/run_audit.hpp"
#include "common/json_input.hpp"
#include "mpm_solver/io/scene_input.hpp"
#include "mpm_solver/app/scene_overrides.hpp"
#include "database/store/audit_log.hpp"
#include "database/store/library.hpp"

namespace grainbank::mpm::app {

namespace {

const char* source_name(StressSource s) {
  switch (s) {
    case StressSource::analytic: return "analytic";
    case StressSource::live: return "live";
    case StressSource::hit: return "hit";
    case StressSource::miss: return "miss";
  }
  return "?";
}

io::AuditTrail read_trail(const std::filesystem::path& run) {
  const std::filesystem::path file = run / io::kAuditTrailFile;
  if (!std::filesystem::exists(file))
    throw common::InputError(file.string() +
                             ": not found; the run recorded no audit trail (add \"audit\": {\"points\": N} to its "
                             "scene and run it again)");
  io::AuditTrail trail = io::read_audit_trail(file);
  if (trail.start_time != 0)
    throw common::InputError(file.string() + ": the run resumed from a restart at t = " +
                             std::to_string(trail.start_time) +
                             " s, so its trail lacks the history before; audit a run started from t = 0");
  return trail;
}

// The run's scene with its DEM-backed materials live and their cell and library paths absolute.
nlohmann::json live_scene(const io::AuditTrail& trail) {
  const std::filesystem::path scene = trail.scene;
  SceneOverrides live;
  live.law = "live";
  return apply_overrides(common::load_json_file(scene), scene.parent_path(), live);
}

// The libraries of the scene's materials, each once.
std::set<std::string> libraries_of(const nlohmann::json& scene) {
  std::set<std::string> out;
  for (const auto& m : scene["materials"])
    if (m.contains("library")) out.insert(m["library"].get<std::string>());
  return out;
}

void write_steps_csv(const audit::RunAudit& audit, const std::filesystem::path& file) {
  std::ofstream out(file);
  out << "point,step,time,source,relative_error,run_sxx,run_syy,run_sxy,run_szz,live_sxx,live_syy,live_sxy,live_szz\n";
  out << std::setprecision(17);
  for (const audit::StepComparison& c : audit.steps) {
    out << c.point << ',' << c.step << ',' << c.time << ',' << source_name(c.source) << ',' << c.relative_error;
    for (const PointStress* s : {&c.run, &c.live})
      out << ',' << s->in_plane(0, 0) << ',' << s->in_plane(1, 1) << ',' << s->in_plane(0, 1) << ',' << s->zz;
    out << '\n';
  }
  if (!out) throw std::runtime_error(file.string() + ": cannot be written");
}

void print_report(const nlohmann::json& s, std::ostream& out) {
  out << "audit of the run " << s["run"].get<std::string>() << ": " << s["points"].size() << " point(s), "
      << s["steps_compared"] << " point-steps re-run live\n"
      << "relative stress error (floor " << s["stress_floor_pa"].get<double>() << " Pa)      count     median        p95        max\n";
  for (const char* key : {"hit", "miss", "live", "cached", "all"}) {
    const auto& e = key == std::string("cached") || key == std::string("all") ? s[key] : s["by_source"][key];
    out << "  " << std::left << std::setw(34) << key << std::right << std::setw(8) << e["count"].get<std::size_t>()
        << std::setw(11) << std::setprecision(3) << e["median"].get<double>() << std::setw(11) << e["p95"].get<double>()
        << std::setw(11) << e["max"].get<double>() << "\n";
  }
}

}  // namespace

nlohmann::json run_audit_command(const AuditCommandOptions& options, std::ostream& out) {
  const io::AuditTrail trail = read_trail(options.run);
  const std::filesystem::path directory = options.run / "audit";
  std::filesystem::create_directories(directory);
  const nlohmann::json scene = live_scene(trail);
  const std::filesystem::path scene_file = directory / "scene_live.json";
  std::ofstream(scene_file) << scene.dump(2) << '\n';
  const io::Scene reference = io::load_scene(scene_file);
  Solver& solver = *reference.solver;

  const audit::RunAudit audit = audit::audit_run(trail, [&](std::uint32_t id) {
    const auto& points = solver.points();
    const auto it = std::find_if(points.begin(), points.end(), [&](const MaterialPoint& p) { return p.id == id; });
    if (it == points.end())
      throw common::InputError(trail.scene + ": has no material point " + std::to_string(id) +
                               " of the audit trail (was the scene changed after the run?)");
    return audit::ReferenceSlot{&solver.law(it->law), it->slot};
  });

  nlohmann::json summary = {{"kind", "mpm_run"},
                            {"run", std::filesystem::absolute(options.run).string()},
                            {"scene", trail.scene},
                            {"points", nlohmann::json::array()},
                            {"steps_compared", audit.steps.size()},
                            {"stress_floor_pa", audit.stress_floor},
                            {"by_source", {{"hit", grainbank::audit::summary_of(audit.hit)},
                                           {"miss", grainbank::audit::summary_of(audit.miss)},
                                           {"live", grainbank::audit::summary_of(audit.live)}}},
                            {"cached", grainbank::audit::summary_of(audit.cached)},
                            {"all", grainbank::audit::summary_of(audit.all)},
                            {"outputs", {{"directory", std::filesystem::absolute(directory).string()}}}};
  for (const io::PointTrail& p : trail.points) summary["points"].push_back(p.id);
  write_steps_csv(audit, directory / "run_audit_steps.csv");
  nlohmann::json audit_ids = nlohmann::json::array();
  for (const std::string& lib : libraries_of(scene)) {
    db::Library library = db::Library::open(lib);
    audit_ids.push_back({{"library", lib}, {"audit_id", db::record_audit(library.catalogue(), summary)}});
  }
  summary["catalogue_rows"] = audit_ids;
  std::ofstream(directory / "run_audit.json") << summary.dump(2) << '\n';

  if (options.json) {
    out << summary.dump(2) << "\n";
  } else {
    print_report(summary, out);
    out << "wrote " << (directory / "run_audit.json").string() << " and " << (directory / "run_audit_steps.csv").string()
        << "\nfigures: /usr/bin/python3 " << GRAINBANK_PLOT_RUN_AUDIT_SCRIPT << " " << directory.string() << "\n";
  }
  return summary;
}

}  // namespace grainbank::mpm::app
